// Ambient occlusion against its closed form. A sphere (centre height h, radius r < h) floats
// above a diffuse plane of albedo a. Seen from a plane point at distance d from the centre,
// the sphere lies wholly above the horizon (h > r), covers solid angle with sin(alpha) = r/d
// at elevation cos(theta) = h/d, and its cosine-weighted solid angle is
//   pi sin^2(alpha) cos(theta) = pi r^2 h / d^3,
// so L = a/pi * (pi - pi r^2 h / d^3) = a (1 - r^2 h / d^3).
// The camera looks straight down on a patch of the plane beside the sphere (no camera ray
// hits the sphere); the expected pixel value averages the closed form over the pixel.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr double kAlbedo = 0.5, kRadius = 1.0, kHeight = 2.0;
constexpr int kSize = 32, kSpp = 4096;

json aoScene(const std::string& sampling) {
    return {
        {"camera", test::topDownCamera(3.0, 0.0, 1.5)},
        {"film", {{"width", kSize}, {"height", kSize}}},
        {"sampler", {{"spp", kSpp}, {"seed", 7}}},
        {"integrator", {{"type", "ao"}, {"sampling", sampling}}},
        {"materials", {{"plane", {{"type", "diffuse"}, {"albedo", {kAlbedo, kAlbedo, kAlbedo}}}}}},
        {"shapes",
         {{{"type", "quad"}, {"origin", {-50, 0, -50}}, {"edge_u", {0, 0, 100}}, {"edge_v", {100, 0, 0}},
           {"material", "plane"}},
          {{"type", "sphere"}, {"center", {0, kHeight, 0}}, {"radius", kRadius}}}},
    };
}

struct AoResult {
    double mse = 0, predictedMse = 0;
    int failures = 0;
};

AoResult checkAo(const std::string& sampling, double z) {
    json doc = aoScene(sampling);
    // The predicted MSE and the cosine-vs-uniform ratio below are those of independent samples
    // (variance m (a - m) / N); Sobol' samples (the default) stratify the hemisphere and fall
    // far below both (test_sampler_estimates.cpp checks them against this closed form).
    doc["sampler"]["type"] = "independent";
    Scene scene = test::sceneFromJson(doc, "ao-" + sampling);
    Image image = test::renderScene(scene);
    std::vector<double> expected = test::expectedTopDown(scene, [](glm::dvec3 x) {
        double d = std::sqrt(x.x * x.x + x.z * x.z + kHeight * kHeight);
        return kAlbedo * (1.0 - kRadius * kRadius * kHeight / (d * d * d));
    });
    AoResult r;
    for (int i = 0; i < kSize * kSize; ++i) {
        double m = expected[i];
        // Per-sample standard deviation. Cosine: the estimate is a*V, Bernoulli with mean m,
        // variance m (a - m). Uniform: 2 a V cos(theta) has E[X^2] <= 4 a^2 E[cos^2] = 4 a^2 / 3.
        double variance = sampling == "cosine" ? m * (kAlbedo - m) : 4.0 * kAlbedo * kAlbedo / 3.0 - m * m;
        double sigma = std::sqrt(variance / kSpp);
        for (int c = 0; c < 3; ++c) {
            double v = image.rgb[3 * i + c];
            if (std::abs(v - m) > z * sigma) ++r.failures;
        }
        double v = image.rgb[3 * i];
        r.mse += (v - m) * (v - m);
        r.predictedMse += variance / kSpp;
    }
    r.mse /= kSize * kSize;
    r.predictedMse /= kSize * kSize;
    if (r.failures) writeExr(test::outputPath("ao-" + sampling + ".exr"), image);
    return r;
}

}  // namespace

TEST(AmbientOcclusion, MatchesClosedFormAndCosineBeatsUniform) {
    // alpha = 1e-3 over both modes' pixels; all channels of a pixel carry the same estimate.
    double z = test::zScore(1e-3, 2 * kSize * kSize);
    AoResult cosine = checkAo("cosine", z);
    AoResult uniform = checkAo("uniform", z);
    EXPECT_EQ(cosine.failures, 0) << "cosine pixels outside " << z << " sigma";
    EXPECT_EQ(uniform.failures, 0) << "uniform pixels outside " << z << " sigma";
    // Cosine sampling: the measured MSE matches its exact prediction (the mean of 1024
    // squared errors has a relative standard deviation of about sqrt(2/1024) = 4.4%).
    EXPECT_GT(cosine.mse, 0.75 * cosine.predictedMse);
    EXPECT_LT(cosine.mse, 1.3 * cosine.predictedMse);
    // Measurably lower variance than uniform sampling (about 4x lower here).
    EXPECT_LT(cosine.mse, 0.5 * uniform.mse) << "cosine " << cosine.mse << " uniform " << uniform.mse;
}

TEST(AmbientOcclusion, MaxDistanceIgnoresFarOccluders) {
    // With max_distance shorter than the gap to the sphere, nothing occludes: L = albedo.
    json doc = aoScene("cosine");
    doc["integrator"]["max_distance"] = 0.5;
    doc["sampler"]["spp"] = 16;
    Image image = test::renderJson(doc, "ao-maxdist");
    for (float v : image.rgb) ASSERT_NEAR(v, kAlbedo, 1e-6);
}
