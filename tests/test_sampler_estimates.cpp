// The Sobol' sampler through the real render path (loader, renderer, ao.comp on lavapipe),
// against closed forms.
//
// Unbiased: ambient occlusion of a sphere (centre height h, radius r) above a plane of
// albedo a is a (1 - r^2 h / d^3) at distance d from the centre (derived in test_ao.cpp).
// Each pixel has its own scrambling seeds, so pixels are independent and the spread of the
// residuals across pixels gives their standard error: a block t-test (render_helpers.h).
//
// Lower error: a plane under an open sky with uniform hemisphere sampling. Nothing occludes,
// so L = a exactly, and one sample's estimate is a/pi * cos / (1/(2 pi)) = 2 a z with
// z = u.x uniform on [0,1) (squareToUniformHemisphere), variance a^2/3. Independent samples:
// MSE = a^2 / (3N). Sobol': the N = 2^m samples of a pixel are a (0,m,2)-net, so exactly one
// z lies in each interval [k/N, (k+1)/N), uniform there and independent of the others (Owen
// scrambling), which is stratified sampling: MSE = N * (2a)^2 / (12 N^2) / N^2 = a^2 / (3N^3).
// The ratio is N^2 = 256 at 16 spp (Owen 1997: scrambled nets reach O(N^-3) on smooth
// integrands).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr double kAlbedo = 0.5, kRadius = 1.0, kHeight = 2.0;
constexpr int kSize = 32;
constexpr double kAlpha = 1e-3;

// A diffuse plane y = 0 seen from above, optionally with the sphere floating over it.
json aoScene(const std::string& sampler, const std::string& sampling, int spp, bool withSphere) {
    json shapes = {{{"type", "quad"}, {"origin", {-50, 0, -50}}, {"edge_u", {0, 0, 100}}, {"edge_v", {100, 0, 0}},
                    {"material", "plane"}}};
    if (withSphere) shapes.push_back({{"type", "sphere"}, {"center", {0, kHeight, 0}}, {"radius", kRadius}});
    return {
        {"camera", test::topDownCamera(3.0, 0.0, 1.5)},
        {"film", {{"width", kSize}, {"height", kSize}}},
        {"sampler", {{"spp", spp}, {"seed", 3}, {"type", sampler}}},
        {"integrator", {{"type", "ao"}, {"sampling", sampling}}},
        {"materials", {{"plane", {{"type", "diffuse"}, {"albedo", {kAlbedo, kAlbedo, kAlbedo}}}}}},
        {"shapes", shapes},
    };
}

double sphereAo(glm::dvec3 x) {
    double d = std::sqrt(x.x * x.x + x.z * x.z + kHeight * kHeight);
    return kAlbedo * (1.0 - kRadius * kRadius * kHeight / (d * d * d));
}

}  // namespace

TEST(SamplerEstimates, SobolIsUnbiasedOnAmbientOcclusion) {
    // Cosine and uniform sampling, from the first sample index and from an odd sample_offset
    // (a partial render whose samples are not an aligned block must be unbiased too).
    struct Case {
        std::string sampling;
        int offset;
    };
    const std::vector<Case> cases = {{"cosine", 0}, {"uniform", 0}, {"cosine", 3}};
    for (const Case& c : cases) {
        json doc = aoScene("sobol", c.sampling, 256, true);
        doc["sampler"]["sample_offset"] = c.offset;
        const std::string name = "sobol-ao-" + c.sampling + "-" + std::to_string(c.offset);
        Scene scene = test::sceneFromJson(doc, name);
        Image image = test::renderScene(scene);
        std::vector<double> expected = test::expectedTopDown(scene, sphereAo);
        std::string report;
        int failures = test::blockTTest(image, expected, 8, kAlpha, int(cases.size()), &report);
        EXPECT_EQ(failures, 0) << name << ": " << report;
        if (failures) writeExr(test::outputPath(name + ".exr"), image);
    }
}

TEST(SamplerEstimates, SobolBeatsIndependentByTheStratificationFactor) {
    const int spp = 16;
    auto mse = [&](const std::string& sampler) {
        Image image = test::renderJson(aoScene(sampler, "uniform", spp, false), "open-sky-" + sampler);
        return test::meanSquaredError(image, std::vector<double>(size_t(kSize) * kSize, kAlbedo));
    };
    const double independent = mse("independent"), sobol = mse("sobol");
    const double predictedIndependent = kAlbedo * kAlbedo / (3.0 * spp);
    const double predictedSobol = predictedIndependent / (double(spp) * spp);
    std::printf("[ open sky, %d spp ] MSE independent %.4g (predicted %.4g), sobol %.4g (predicted %.4g)\n", spp,
                independent, predictedIndependent, sobol, predictedSobol);
    // Each MSE averages 1024 independent squared errors of near-normal residuals: relative
    // standard deviation sqrt(2/1024) = 4.4%, so [0.75, 1.3] x the prediction is > 5 sigma.
    EXPECT_GT(independent, 0.75 * predictedIndependent);
    EXPECT_LT(independent, 1.3 * predictedIndependent);
    EXPECT_GT(sobol, 0.75 * predictedSobol);
    EXPECT_LT(sobol, 1.3 * predictedSobol);
    // The point of the sampler, with a wide margin under the expected 256x.
    EXPECT_LT(sobol, independent / 64.0) << "sobol " << sobol << " independent " << independent;
}
