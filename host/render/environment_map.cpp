// Equirectangular environment map lookup and importance sampling (see environment_map.h).
// Piecewise-constant 2D distribution over the sphere: PBR book 4th ed. 12.5.2 ("Image
// Infinite Lights") samples by marginal and conditional tables; here one alias table over
// all texels gives the same distribution with one lookup per draw.
#include "render/environment_map.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/stop_request.h"
#include "render/alias_table.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

double luminance(glm::vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

}  // namespace

glm::uvec2 environmentTexel(glm::dvec3 d, uint32_t width, uint32_t height) {
    double u = std::atan2(d.x, -d.z) / (2.0 * kPi);
    u -= std::floor(u);  // wrapped to [0, 1)
    double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi;
    uint32_t col = std::min(uint32_t(u * width), width - 1);
    uint32_t row = std::min(uint32_t(v * height), height - 1);
    return {col, row};
}

double environmentTexelSolidAngle(uint32_t row, uint32_t width, uint32_t height) {
    double theta0 = kPi * row / height, theta1 = kPi * (row + 1) / height;
    return (2.0 * kPi / width) * (std::cos(theta0) - std::cos(theta1));
}

glm::vec3 environmentMapRadiance(const EnvironmentImage& image, glm::dvec3 d) {
    glm::uvec2 t = environmentTexel(d, image.width, image.height);
    return image.texels[size_t(t.y) * image.width + t.x];
}

void writeEnvironmentTexels(const EnvironmentImage& image, glm::vec4* out) {
    for (glm::vec3 texel : image.texels) *out++ = glm::vec4(texel, 0.0f);
}

std::vector<gpu::AliasEntry> buildEnvironmentTable(const EnvironmentImage& image, bool* black) {
    const size_t n = size_t(image.width) * image.height;
    std::vector<double> weights(n);
    double total = 0.0;
    for (uint32_t row = 0; row < image.height; ++row) {
        throwIfStopRequested();  // batch: a stop during a large map's table waits one row
        double omega = environmentTexelSolidAngle(row, image.width, image.height);
        for (uint32_t col = 0; col < image.width; ++col) {
            size_t i = size_t(row) * image.width + col;
            weights[i] = luminance(image.texels[i]) * omega;
            total += weights[i];
        }
    }
    const bool noEmission = !(total > 0.0);
    if (black) *black = noEmission;
    if (noEmission)
        for (uint32_t row = 0; row < image.height; ++row)
            std::fill_n(weights.begin() + ptrdiff_t(size_t(row) * image.width), image.width,
                        environmentTexelSolidAngle(row, image.width, image.height));
    return buildAliasTableInPlace(weights);
}

EnvironmentDistribution buildEnvironmentDistribution(EnvironmentImage image) {
    EnvironmentDistribution dist;
    dist.table = buildEnvironmentTable(image, &dist.black);
    dist.image = std::move(image);
    return dist;
}

uint32_t environmentAliasSlot(glm::dvec2 u, uint32_t count, double* coin) {
    // slot + coin = (a 2^24 + b) count / 2^48 in exact integers; the coin keeps the top 24
    // bits of the fraction, as the GPU's umulExtended version does.
    uint64_t a = uint64_t(u.x * 16777216.0), b = uint64_t(u.y * 16777216.0);
    unsigned __int128 x = (unsigned __int128)((a << 24) | b) * count;
    uint64_t slot = uint64_t(x >> 48);
    *coin = double(uint64_t(x >> 24) & 0xffffffu) / 16777216.0;
    return uint32_t(std::min<uint64_t>(slot, count - 1));
}

glm::dvec3 sampleEnvironmentMap(const EnvironmentDistribution& dist, glm::dvec3 u, double* pdf) {
    const uint32_t w = dist.image.width, h = dist.image.height;
    double coin = 0.0;
    gpu::AliasEntry e = dist.table[environmentAliasSlot({u.x, u.y}, uint32_t(dist.table.size()), &coin)];
    // The coin, rescaled within the side it fell on, is uniform again: phi within the column.
    double within;
    if (coin < e.probability) {
        within = coin / e.probability;
    } else {
        within = (coin - e.probability) / (1.0 - e.probability);
        e = dist.table[e.alias];
    }
    uint32_t col = e.item % w, row = e.item / w;
    double phi = 2.0 * kPi * (col + std::min(within, 1.0 - 1e-16)) / w;
    double cos0 = std::cos(kPi * row / h), cos1 = std::cos(kPi * (row + 1) / h);
    double cosTheta = cos0 - u.z * (cos0 - cos1);
    double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    // Inverse of environmentTexel's u = atan2(d.x, -d.z) / (2 pi), v = acos(d.y) / pi.
    glm::dvec3 d(sinTheta * std::sin(phi), cosTheta, -sinTheta * std::cos(phi));
    if (pdf) *pdf = double(e.pmf) / environmentTexelSolidAngle(row, w, h);
    return d;
}

double environmentMapPdf(const EnvironmentDistribution& dist, glm::dvec3 d) {
    glm::uvec2 t = environmentTexel(d, dist.image.width, dist.image.height);
    size_t i = size_t(t.y) * dist.image.width + t.x;
    return double(dist.table[i].pmf) / environmentTexelSolidAngle(t.y, dist.image.width, dist.image.height);
}

}  // namespace penumbra
