// Environment-map sampling as GLSL on lavapipe (shaders/lights/environment_map.glsl through
// sampleLight and lightPdf, tests/light_kernel.h): for a tiny bright sun, a smooth gradient,
// one bright texel at the pole and a black map, the sampled directions pass a chi-square test
// against the pdf the GPU evaluates, that pdf integrates to 1 and equals the host's
// (render/environment_map.cpp) and each sample's own pdf, the radiance is the texel's, and
// nothing is NaN. A wrong pdf (texel area in (phi, theta) in place of solid angle) must fail.
// Cells: each texel split 2 x 2 (tests/environment_test_maps.h), so that the expected count
// of a cell is exactly N pdf Omega(cell).
// Significance: alpha = 0.01 per test, Sidak-corrected over the 4 maps; fixed seeds.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "chi2.h"
#include "environment_test_maps.h"
#include "light_kernel.h"
#include "render/scene_arrays.h"

using namespace penumbra;

namespace {

constexpr uint32_t kSamples = 1u << 20;
constexpr int kChi2Tests = 4;

SceneArrays mapArrays(const std::string& kind) {
    Scene scene;
    scene.materials.push_back(Material{});
    Light env;
    env.type = LightType::Environment;
    env.intensity = glm::vec3(1.0f);
    env.map = std::make_shared<const EnvironmentImage>(test::makeMap(kind));
    scene.lights.push_back(env);
    return buildSceneArrays(scene);
}

struct GpuDraw {
    std::vector<double> counts;     // per cell
    size_t declined = 0;            // sampleLight returned false
    size_t nonFinite = 0;           // NaN or infinite direction, pdf or radiance
    size_t pdfMismatches = 0;       // sample pdf != lightPdf at the sampled direction
    size_t radianceMismatches = 0;  // radiance != the texel the direction looks up
};

GpuDraw drawOnGpu(test::LightKernel& kernel, const EnvironmentImage& map, uint32_t seed) {
    // The shading point and normal do not matter to a map (it is sampled over the sphere).
    auto records = kernel.sample(0, glm::vec3(0.5f, 1.0f, -2.0f), glm::vec3(0.0f, 1.0f, 0.0f), gpu::SPHERE_SOLID_ANGLE,
                                 seed, kSamples);
    GpuDraw out;
    out.counts.assign(size_t(test::kW) * test::kH * 4, 0.0);
    for (const auto& r : records) {
        if (!(r.flags & gpu::LIGHT_TEST_ACCEPTED)) {
            ++out.declined;
            continue;
        }
        bool finite = std::isfinite(r.pdf) && std::isfinite(r.tracedPdf);
        for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(r.wi[c]) && std::isfinite(r.radiance[c]);
        if (!finite) {
            ++out.nonFinite;
            continue;
        }
        glm::dvec3 d = glm::normalize(glm::dvec3(r.wi));
        out.counts[test::cellOf(d)] += 1;
        if (!(std::abs(r.pdf - r.tracedPdf) <= 1e-5 * r.pdf)) ++out.pdfMismatches;
        if (r.radiance != environmentMapRadiance(map, d)) ++out.radianceMismatches;
    }
    return out;
}

// Probabilities of the cells from the GPU's pdf at their centres.
std::vector<double> gpuCellProbabilities(test::LightKernel& kernel) {
    std::vector<glm::dvec3> centres = test::cellCentres();
    std::vector<glm::vec3> dirs(centres.begin(), centres.end());
    std::vector<double> pdf =
        kernel.pdf(0, glm::vec3(0.5f, 1.0f, -2.0f), glm::vec3(0.0f, 1.0f, 0.0f), gpu::SPHERE_SOLID_ANGLE, dirs);
    std::vector<double> p(pdf.size());
    for (size_t cell = 0; cell < p.size(); ++cell) p[cell] = pdf[cell] * test::cellSolidAngle(cell);
    return p;
}

}  // namespace

class EnvironmentMapGpu : public ::testing::TestWithParam<const char*> {};

TEST_P(EnvironmentMapGpu, SamplesMatchTheirPdfWhichIntegratesToOne) {
    const std::string kind = GetParam();
    SceneArrays arrays = mapArrays(kind);
    ASSERT_EQ(arrays.environmentTable.size(), size_t(test::kW) * test::kH);
    test::LightKernel kernel(arrays);
    EnvironmentImage map = test::makeMap(kind);
    GpuDraw drawn = drawOnGpu(kernel, map, 31);
    EXPECT_EQ(drawn.nonFinite, 0u) << kind;
    EXPECT_EQ(drawn.declined, 0u) << kind << ": every texel has a positive pmf (a black map: uniform)";
    // A sample within float rounding of a texel edge may be looked up in the neighbour:
    // at most a few in a million.
    EXPECT_LE(drawn.pdfMismatches, kSamples / 100000) << kind << ": sampled pdf differs from the evaluated pdf";
    EXPECT_LE(drawn.radianceMismatches, kSamples / 100000) << kind << ": radiance differs from the texel's";

    std::vector<double> p = gpuCellProbabilities(kernel);
    // The GPU's pdf is the host's (float against double).
    EnvironmentDistribution dist = buildEnvironmentDistribution(map);
    std::vector<glm::dvec3> centres = test::cellCentres();
    size_t differ = 0;
    for (size_t cell = 0; cell < p.size(); ++cell) {
        double host = environmentMapPdf(dist, centres[cell]) * test::cellSolidAngle(cell);
        if (!(std::abs(p[cell] - host) <= 1e-5 * host)) ++differ;
    }
    EXPECT_EQ(differ, 0u) << kind << ": GPU pdf differs from the host's";
    double sum = 0;
    for (double x : p) sum += x;
    EXPECT_NEAR(sum, 1.0, 1e-5) << kind << ": pdf times solid angle summed over the texels";
    for (double& x : p) x /= sum;  // float pmfs may sum to 1 + 1e-7; the shape is tested here
    test::DiscreteChi2Options options;
    options.numTests = kChi2Tests;
    options.dumpName = "environment-gpu-" + kind;
    test::Chi2Result r = test::chi2TestDiscrete(drawn.counts, p, 0, options);
    EXPECT_TRUE(r.passed) << kind << ": " << r.message;
    std::printf("[ environment %s ] %s\n", kind.c_str(), r.message.c_str());
}

INSTANTIATE_TEST_SUITE_P(Maps, EnvironmentMapGpu, ::testing::Values("sun", "gradient", "pole", "black"));

TEST(EnvironmentMapGpu, WrongPdfFailsTheChiSquareTest) {
    // The texel's pmf over its area in (phi, theta) instead of its solid angle: right at the
    // equator, off by sin(theta) elsewhere. The GPU's samples are right; this pdf is not theirs.
    SceneArrays arrays = mapArrays("gradient");
    test::LightKernel kernel(arrays);
    GpuDraw drawn = drawOnGpu(kernel, test::makeMap("gradient"), 31);
    std::vector<double> p = gpuCellProbabilities(kernel);
    double sum = 0;
    for (size_t cell = 0; cell < p.size(); ++cell) {
        double area = (2 * test::kEnvPi / test::kW) * (test::kEnvPi / test::kH) / 4;
        p[cell] *= area / test::cellSolidAngle(cell);
        sum += p[cell];
    }
    for (double& x : p) x /= sum;  // even renormalized, the shape is wrong
    test::Chi2Result r = test::chi2TestDiscrete(drawn.counts, p, 0, {});
    EXPECT_FALSE(r.passed) << r.message;
}
