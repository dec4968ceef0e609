// The two samplers of shaders/common/rng.glsl, drawn on the GPU (lavapipe) through
// shaders/tests/rng.comp, exactly as the integrators call them (rand2 from dimension 0 on).
// Sobol: every value lies in [0,1) on the 24-bit grid; every aligned block of 2^m sample
// indices of a (pixel, seed, dimension) is a (0,m,2)-net for m = 0..10; each point is
// uniform over pixels (chi-square), which is what keeps estimates unbiased; dimension pairs
// and neighbouring pixels are uncorrelated. Independent: still the pcg4d hash it always was
// (bit for bit) and, unlike Sobol, not a net, so the type switch itself is tested.
//
// Significance: alpha = 1e-3 for the statistical checks of this file, Bonferroni/Sidak-
// corrected over their count; the net checks are exact. Seeds are fixed.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "chi2.h"
#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu_fixture.h"
#include "render_helpers.h"
#include "shared/types.h"
#include "tests/rng_test.h"

using namespace penumbra;
using gpu::RngPush;

namespace {

constexpr double kAlpha = 1e-3;
constexpr int kMaxLog2 = 10;                    // nets checked up to 2^10 points
constexpr uint32_t kBlock = 1u << kMaxLog2;
constexpr uint32_t kDimensions = 24;            // rand2 calls per sample: dimensions 0..23

// The sampler test kernel, created once (lavapipe compiles on the first dispatch).
class SamplerKernel {
public:
    SamplerKernel()
        : m_ctx(test::gpuContext()),
          m_kernel(m_ctx, "tests/rng", {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, sizeof(RngPush)) {}

    // out[(j * count + i) * dimensionCount + d], see tests/rng_test.h.
    std::vector<glm::vec2> draw(const RngPush& push) {
        const size_t n = size_t(push.pixelCount) * push.count * push.dimensionCount;
        gpu::Buffer out(m_ctx, VkDeviceSize(n) * sizeof(glm::vec2), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
        m_kernel.bind(0, out);
        m_kernel.run((push.count + gpu::RNG_WORKGROUP_SIZE - 1) / gpu::RNG_WORKGROUP_SIZE, push.pixelCount, 1, &push);
        return out.read<glm::vec2>();
    }

private:
    gpu::Context& m_ctx;
    gpu::Kernel m_kernel;
};

SamplerKernel& samplerKernel() {
    static SamplerKernel kernel;
    return kernel;
}

// `count` samples from `firstIndex` of one pixel, all kDimensions pairs.
std::vector<glm::vec2> drawPixel(uint32_t sampler, uint32_t seed, uint32_t pixel, uint32_t firstIndex,
                                 uint32_t count) {
    return samplerKernel().draw({sampler, seed, pixel, 1, 1, firstIndex, count, kDimensions});
}

// Dimension pair d of sample i (relative to the drawn range).
glm::vec2 at(const std::vector<glm::vec2>& values, uint32_t i, uint32_t d) { return values[size_t(i) * kDimensions + d]; }

// Whether points [first, first + 2^m) of dimension d are a (0,m,2)-net in base 2: every
// elementary interval [a/2^i, (a+1)/2^i) x [b/2^j, (b+1)/2^j) with i + j = m holds exactly
// one point. Values are multiples of 2^-24 (m <= 10 < 24), so the cell index is exact.
bool isNet(const std::vector<glm::vec2>& values, uint32_t first, int m, uint32_t d) {
    const uint32_t n = 1u << m;
    std::vector<uint8_t> seen(n);
    for (int i = 0; i <= m; ++i) {
        std::fill(seen.begin(), seen.end(), 0);
        for (uint32_t k = 0; k < n; ++k) {
            glm::vec2 p = at(values, first + k, d);
            uint32_t a = uint32_t(double(p.x) * double(1u << i)), b = uint32_t(double(p.y) * double(1u << (m - i)));
            if (seen[(a << (m - i)) | b]++) return false;
        }
    }
    return true;
}

// pcg4d of shaders/common/rng.glsl (Jarzynski & Olano 2020), the independent sampler's hash.
std::array<uint32_t, 4> pcg4d(std::array<uint32_t, 4> v) {
    for (uint32_t& x : v) x = x * 1664525u + 1013904223u;
    auto mix = [&] {
        v[0] += v[1] * v[3];
        v[1] += v[2] * v[0];
        v[2] += v[0] * v[1];
        v[3] += v[1] * v[2];
    };
    mix();
    for (uint32_t& x : v) x ^= x >> 16;
    mix();
    return v;
}

float bitsToUnit(uint32_t bits) { return float(bits >> 8) * (1.0f / 16777216.0f); }

struct PixelSeed {
    uint32_t pixel, seed;
};
// Neighbouring pixels, a far one, the largest seed a scene may give.
const std::vector<PixelSeed> kPixelSeeds = {{0, 0}, {1, 0}, {123457, 7}, {1u << 24, 2147483647u}};
// First sample indices of the drawn ranges: a pixel's first samples, a later aligned block,
// and the last block below 2^32 (sample_offset + i can reach 2^32 - 2).
const std::vector<uint32_t> kFirstIndices = {0, 37 * kBlock, 0u - kBlock};

}  // namespace

TEST(Sampler, ValuesLieInTheUnitSquareOn24BitGrid) {
    for (uint32_t sampler : {gpu::SAMPLER_SOBOL, gpu::SAMPLER_INDEPENDENT})
        for (const PixelSeed& ps : kPixelSeeds)
            for (uint32_t first : kFirstIndices) {
                const auto values = drawPixel(sampler, ps.seed, ps.pixel, first, kBlock);
                for (const glm::vec2& v : values)
                    for (float c : {v.x, v.y}) {
                        ASSERT_TRUE(c >= 0.0f && c < 1.0f) << c;
                        ASSERT_EQ(std::ldexp(double(c), 24), std::floor(std::ldexp(double(c), 24))) << c;
                    }
            }
}

TEST(Sampler, SobolAlignedBlocksOfEveryPixelAndPairAreNets) {
    // Every aligned block of 2^m indices in each drawn range: for the range starting at 0 that
    // includes the first 2^m samples of the pixel for every m.
    int checked = 0;
    for (const PixelSeed& ps : kPixelSeeds)
        for (uint32_t first : kFirstIndices) {
            const auto values = drawPixel(gpu::SAMPLER_SOBOL, ps.seed, ps.pixel, first, kBlock);
            for (uint32_t d = 0; d < kDimensions; ++d)
                for (int m = 0; m <= kMaxLog2; ++m)
                    for (uint32_t block = 0; block < kBlock; block += 1u << m) {
                        ASSERT_TRUE(isNet(values, block, m, d))
                            << "pixel " << ps.pixel << " seed " << ps.seed << " dimension " << d << ": indices ["
                            << first + block << ", " << first + block + (1u << m) << ") are not a (0," << m
                            << ",2)-net";
                        ++checked;
                    }
        }
    EXPECT_EQ(checked, int(kPixelSeeds.size() * kFirstIndices.size() * kDimensions * (2 * kBlock - 1)));
}

TEST(Sampler, IndependentIsTheUnchangedHashAndNotANet) {
    // The independent sampler is still pcg4d(pixel, sample index, seed, dimension), bit for bit.
    for (const PixelSeed& ps : kPixelSeeds)
        for (uint32_t first : kFirstIndices) {
            const auto values = drawPixel(gpu::SAMPLER_INDEPENDENT, ps.seed, ps.pixel, first, 64);
            for (uint32_t i = 0; i < 64; ++i)
                for (uint32_t d = 0; d < kDimensions; ++d) {
                    auto h = pcg4d({ps.pixel, first + i, ps.seed, d});
                    ASSERT_EQ(at(values, i, d), glm::vec2(bitsToUnit(h[0]), bitsToUnit(h[1])))
                        << "pixel " << ps.pixel << " index " << first + i << " dimension " << d;
                }
        }
    // Independent points are not nets: 2^m random points fill the 2^m cells of even one
    // partition with probability (2^m)! / (2^m)^(2^m), about 1e-6 for m = 4.
    const auto values = drawPixel(gpu::SAMPLER_INDEPENDENT, 0, 0, 0, kBlock);
    for (uint32_t d = 0; d < kDimensions; ++d)
        for (int m = 4; m <= kMaxLog2; ++m) EXPECT_FALSE(isNet(values, 0, m, d)) << "dimension " << d << ", m = " << m;
}

TEST(Sampler, SobolPointIsUniformOverPixels) {
    // A fixed (sample index, dimension) over many pixels: each pixel has its own seeds, so the
    // values are independent draws of that point, and uniform if the scrambling is. Chi-square
    // against the uniform density on 32 x 32 cells (32 expected points per cell).
    const uint32_t pixels = 32768;
    const std::vector<uint32_t> indices = {0, 1, 6, 1000, 0x80000003u};
    const std::vector<uint32_t> dimensions = {0, 1, 21};
    for (uint32_t index : indices) {
        const auto values = samplerKernel().draw({gpu::SAMPLER_SOBOL, 3, 0, 1, pixels, index, 1, kDimensions});
        for (uint32_t d : dimensions) {
            std::vector<glm::dvec2> points(pixels);
            for (uint32_t p = 0; p < pixels; ++p) points[p] = glm::dvec2(values[size_t(p) * kDimensions + d]);
            test::SquareChi2Options options;
            options.res = 32;
            options.significance = kAlpha;
            options.numTests = int(indices.size() * dimensions.size());
            options.dumpName = "chi2_sobol_index" + std::to_string(index) + "_dim" + std::to_string(d);
            const auto r = test::chi2TestSquare(
                points, [](const std::vector<glm::dvec2>& q) { return std::vector<double>(q.size(), 1.0); }, options);
            EXPECT_TRUE(r.passed) << "index " << index << " dimension " << d << ": " << r.message;
        }
    }
}

TEST(Sampler, SobolDecorrelatesDimensionPairsAndNeighbouringPixels) {
    // Over N samples of a pixel, the sample mean of (u - 1/2)(v - 1/2) for two coordinates u, v
    // that should be independent has expectation exactly 0: u and v come from independently
    // seeded scrambles (dimension d and d + 1 of a pixel; the same dimension of pixels p and
    // p + 1). Pixels are independent of each other, so the across-pixel spread of that mean
    // gives its standard error; |mean over pixels| <= z * sd / sqrt(pixels). Sharing seeds
    // between the two (dimension or pixel left out of the hash) would give 1/12 instead,
    // hundreds of standard errors away.
    const uint32_t pixels = 16384, n = 16;
    const auto values = samplerKernel().draw({gpu::SAMPLER_SOBOL, 5, 0, 1, pixels, 0, n, kDimensions});
    auto value = [&](uint32_t p, uint32_t i, uint32_t d) { return values[(size_t(p) * n + i) * kDimensions + d]; };

    // Pair statistics: x.x, y.y and x.y of dimensions d and d + 1, for every d; x.x and y.y of
    // pixels 2k and 2k + 1 (disjoint pairs, so the terms stay independent), for every d.
    const int tests = 3 * int(kDimensions - 1) + 2 * int(kDimensions);
    const double z = test::zScore(kAlpha, tests);
    auto check = [&](const std::string& what, uint32_t count, auto&& perPixelMean) {
        double sum = 0, sum2 = 0;
        for (uint32_t k = 0; k < count; ++k) {
            double c = perPixelMean(k);
            sum += c;
            sum2 += c * c;
        }
        double mean = sum / count, sd = std::sqrt(std::max(0.0, (sum2 - count * mean * mean) / (count - 1)));
        EXPECT_LE(std::abs(mean), z * sd / std::sqrt(double(count)))
            << what << ": mean " << mean << ", standard error " << sd / std::sqrt(double(count));
    };
    auto centred = [](float u) { return double(u) - 0.5; };
    for (uint32_t d = 0; d + 1 < kDimensions; ++d) {
        const std::string pair = "dimensions " + std::to_string(d) + ", " + std::to_string(d + 1);
        for (int c = 0; c < 3; ++c)
            check(pair + " statistic " + std::to_string(c), pixels, [&](uint32_t p) {
                double s = 0;
                for (uint32_t i = 0; i < n; ++i) {
                    glm::vec2 a = value(p, i, d), b = value(p, i, d + 1);
                    s += c == 0 ? centred(a.x) * centred(b.x) : c == 1 ? centred(a.y) * centred(b.y)
                                                                       : centred(a.x) * centred(b.y);
                }
                return s / n;
            });
    }
    for (uint32_t d = 0; d < kDimensions; ++d)
        for (int c = 0; c < 2; ++c)
            check("pixels 2k, 2k+1, dimension " + std::to_string(d) + " coordinate " + std::to_string(c), pixels / 2,
                  [&](uint32_t k) {
                      double s = 0;
                      for (uint32_t i = 0; i < n; ++i) {
                          glm::vec2 a = value(2 * k, i, d), b = value(2 * k + 1, i, d);
                          s += c == 0 ? centred(a.x) * centred(b.x) : centred(a.y) * centred(b.y);
                      }
                      return s / n;
                  });
}
