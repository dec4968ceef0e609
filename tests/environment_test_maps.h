// Small environment maps for the tests of environment-map sampling (host and GPU): a tiny
// bright sun, a smooth gradient, one bright texel at the pole and a black map, and the cells
// their samples are counted in: each texel split 2 x 2 in phi and cos(theta), of equal solid
// angle, so that the expected count of a cell is exactly N pdf(cell) Omega(cell).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "render/environment_map.h"

namespace penumbra::test {

inline constexpr double kEnvPi = std::numbers::pi;
inline constexpr uint32_t kW = 32, kH = 16;

inline EnvironmentImage makeMap(const std::string& kind) {
    EnvironmentImage image{kW, kH, std::vector<glm::vec3>(size_t(kW) * kH, glm::vec3(0.0f))};
    for (uint32_t row = 0; row < kH; ++row)
        for (uint32_t col = 0; col < kW; ++col) {
            glm::vec3& t = image.texels[size_t(row) * kW + col];
            if (kind == "sun")
                t = (row == 5 && col == 20) ? glm::vec3(2e4f, 1.5e4f, 1e4f) : glm::vec3(0.1f, 0.2f, 0.4f);
            if (kind == "gradient")
                t = glm::vec3(0.1f + float(row) / kH, 0.5f + 0.4f * float(std::sin(2 * kEnvPi * col / kW)), 0.3f);
            if (kind == "pole") t = (row == 0 && col == 7) ? glm::vec3(1e5f) : glm::vec3(0.01f);
        }
    return image;
}

// The cell (texel, quarter) of a direction: texel by the contract's lookup, then which half
// of the texel's phi range and of its cos(theta) range.
inline size_t cellOf(glm::dvec3 d) {
    glm::uvec2 t = environmentTexel(d, kW, kH);
    double u = std::atan2(d.x, -d.z) / (2 * kEnvPi);
    u -= std::floor(u);
    double fu = u * kW - t.x;
    double cos0 = std::cos(kEnvPi * t.y / kH), cos1 = std::cos(kEnvPi * (t.y + 1) / kH);
    double fv = (cos0 - d.y) / (cos0 - cos1);
    size_t q = (fu >= 0.5 ? 1 : 0) + (fv >= 0.5 ? 2 : 0);
    return (size_t(t.y) * kW + t.x) * 4 + q;
}

// The centre direction of cell (texel i, quarter q), for evaluating a pdf there.
inline glm::dvec3 cellCentre(size_t cell) {
    size_t i = cell / 4, q = cell % 4;
    uint32_t col = uint32_t(i % kW), row = uint32_t(i / kW);
    double phi = 2 * kEnvPi * (col + (q & 1 ? 0.75 : 0.25)) / kW;
    double cos0 = std::cos(kEnvPi * row / kH), cos1 = std::cos(kEnvPi * (row + 1) / kH);
    double c = cos0 - (q & 2 ? 0.75 : 0.25) * (cos0 - cos1);
    double s = std::sqrt(std::max(0.0, 1 - c * c));
    return {s * std::sin(phi), c, -s * std::cos(phi)};
}

// Probability of every cell from a pdf evaluated at its centre (constant over a texel).
inline std::vector<double> cellProbabilities(const std::function<double(glm::dvec3)>& pdf) {
    std::vector<double> p(size_t(kW) * kH * 4);
    for (size_t cell = 0; cell < p.size(); ++cell)
        p[cell] = pdf(cellCentre(cell)) * environmentTexelSolidAngle(uint32_t(cell / 4 / kW), kW, kH) / 4;
    return p;
}

// The centres of all cells, in cell order (for a pdf evaluated elsewhere, e.g. on the GPU).
inline std::vector<glm::dvec3> cellCentres() {
    std::vector<glm::dvec3> out(size_t(kW) * kH * 4);
    for (size_t cell = 0; cell < out.size(); ++cell) out[cell] = cellCentre(cell);
    return out;
}

// The solid angle of one cell (a quarter of its texel's).
inline double cellSolidAngle(size_t cell) { return environmentTexelSolidAngle(uint32_t(cell / 4 / kW), kW, kH) / 4; }

}  // namespace penumbra::test
