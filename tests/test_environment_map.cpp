// The environment map's lookup and importance sampling on the host (render/environment_map.h):
// the contract's orientation, chi-square of the sampled directions against the evaluated pdf
// for a tiny bright sun, a smooth gradient, one bright texel at the pole and a black map, the
// pdf integrating to 1, every sample's pdf equal to the pdf evaluated at its direction, and a
// wrong pdf (texel area in (u, v) in place of solid angle) failing the same chi-square test.
// Cells: each texel split 2 x 2 in phi and cos(theta), of equal solid angle, so the expected
// count of a cell is exactly N pdf(cell) Omega(cell) (the pdf is constant over a texel).
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "chi2.h"
#include "environment_test_maps.h"
#include "render/environment_map.h"

using namespace penumbra;

namespace {

using test::cellOf;
using test::cellProbabilities;
using test::kH;
using test::kW;
using test::makeMap;
constexpr double kPi = std::numbers::pi;
constexpr size_t kSamples = 1u << 20;

struct Drawn {
    std::vector<double> counts;
    size_t pdfMismatches = 0;
};

Drawn draw(const EnvironmentDistribution& dist, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    Drawn out;
    out.counts.assign(size_t(kW) * kH * 4, 0.0);
    for (size_t k = 0; k < kSamples; ++k) {
        double pdf = 0.0;
        glm::dvec3 d = sampleEnvironmentMap(dist, {uni(rng), uni(rng), uni(rng)}, &pdf);
        out.counts[cellOf(d)] += 1;
        if (!(std::abs(pdf - environmentMapPdf(dist, d)) <= 1e-9 * pdf)) ++out.pdfMismatches;
    }
    return out;
}

}  // namespace

TEST(EnvironmentMap, LookupFollowsTheContractsOrientation) {
    // u = atan2(d.x, -d.z) / (2 pi) wrapped, v = acos(d.y) / pi, row 0 at +y.
    EXPECT_EQ(environmentTexel({0, 1, 0}, kW, kH).y, 0u);  // any column at the pole
    EXPECT_EQ(environmentTexel({0, -1, 0}, kW, kH).y, kH - 1);
    EXPECT_EQ(environmentTexel({0, 0, -1}, kW, kH), glm::uvec2(0, kH / 2));           // u = 0
    EXPECT_EQ(environmentTexel({1, 0, 0}, kW, kH), glm::uvec2(kW / 4, kH / 2));       // u = 1/4
    EXPECT_EQ(environmentTexel({0, 0, 1}, kW, kH), glm::uvec2(kW / 2, kH / 2));       // u = 1/2
    EXPECT_EQ(environmentTexel({-1, 0, 0}, kW, kH), glm::uvec2(3 * kW / 4, kH / 2));  // u = -1/4 -> 3/4
    double total = 0;
    for (uint32_t row = 0; row < kH; ++row) total += kW * environmentTexelSolidAngle(row, kW, kH);
    EXPECT_NEAR(total, 4 * kPi, 1e-12);
}

class EnvironmentMapSampling : public ::testing::TestWithParam<const char*> {};

TEST_P(EnvironmentMapSampling, MatchesItsPdfWhichIntegratesToOne) {
    const std::string kind = GetParam();
    EnvironmentDistribution dist = buildEnvironmentDistribution(makeMap(kind));
    EXPECT_EQ(dist.black, kind == "black");
    Drawn drawn = draw(dist, 7);
    EXPECT_EQ(drawn.pdfMismatches, 0u) << "sampled pdf differs from the evaluated pdf";

    auto pdf = [&](glm::dvec3 d) { return environmentMapPdf(dist, d); };
    std::vector<double> p = cellProbabilities(pdf);
    double sum = 0;
    for (double x : p) sum += x;
    EXPECT_NEAR(sum, 1.0, 1e-5) << "pdf times solid angle summed over the texels";
    // The alias table's pmfs are floats, each rounded to 2^-24 of itself: their sum may exceed 1
    // by ~1e-7, which the chi-square harness's exact-integral check would call "more than 1".
    // The sum was checked just above; the chi-square test sees the normalized shape.
    for (double& x : p) x /= sum;
    test::DiscreteChi2Options options;
    options.numTests = 4;
    options.dumpName = "environment-" + kind;
    test::Chi2Result r = test::chi2TestDiscrete(drawn.counts, p, 0, options);
    EXPECT_TRUE(r.passed) << kind << ": " << r.message;

    // The pdf integrates to 1 over the sphere, by Monte Carlo over uniform directions:
    // mean of 4 pi pdf, within 5 standard errors (its own sample variance).
    std::mt19937_64 rng(99);
    std::normal_distribution<double> gauss;
    double m = 0, m2 = 0;
    const size_t n = 1u << 18;
    for (size_t k = 0; k < n; ++k) {
        glm::dvec3 d = glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
        double v = 4 * kPi * pdf(d);
        ASSERT_TRUE(std::isfinite(v));
        m += v;
        m2 += v * v;
    }
    m /= n;
    double sigma = std::sqrt(std::max(0.0, m2 / n - m * m) / n);
    EXPECT_NEAR(m, 1.0, 5 * sigma + 1e-6) << kind;
}

INSTANTIATE_TEST_SUITE_P(Maps, EnvironmentMapSampling, ::testing::Values("sun", "gradient", "pole", "black"));

TEST(EnvironmentMap, WrongPdfFailsTheChiSquareTest) {
    // The texel's pmf over its area in (phi, theta) instead of its solid angle: right at the
    // equator, off by sin(theta) elsewhere. The samples are the right ones; the test must
    // notice that this pdf is not theirs.
    EnvironmentDistribution dist = buildEnvironmentDistribution(makeMap("gradient"));
    Drawn drawn = draw(dist, 7);
    auto wrong = [&](glm::dvec3 d) {
        glm::uvec2 t = environmentTexel(d, kW, kH);
        double area = (2 * kPi / kW) * (kPi / kH);
        return double(dist.table[size_t(t.y) * kW + t.x].pmf) / area;
    };
    std::vector<double> p = cellProbabilities(wrong);
    double sum = 0;
    for (double& x : p) sum += x;
    for (double& x : p) x /= sum;  // even renormalized, the shape is wrong
    test::Chi2Result r = test::chi2TestDiscrete(drawn.counts, p, 0, {});
    EXPECT_FALSE(r.passed) << r.message;
}

TEST(EnvironmentMap, BlackMapSamplesUniformlyWithFinitePdf) {
    EnvironmentDistribution dist = buildEnvironmentDistribution(makeMap("black"));
    EXPECT_TRUE(dist.black);
    for (glm::dvec3 d : {glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0), glm::dvec3(0.6, 0, 0.8)})
        EXPECT_NEAR(environmentMapPdf(dist, d), 1 / (4 * kPi), 1e-6);
    EXPECT_EQ(environmentMapRadiance(dist.image, {0, 1, 0}), glm::vec3(0.0f));
}
