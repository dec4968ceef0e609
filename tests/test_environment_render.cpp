// Environment maps rendered end to end (scene file -> loader -> GPU): the irradiance on an
// unoccluded diffuse floor under a map equals the exact sum over texels of radiance times
// projected solid angle, under every strategy; a constant map renders as the constant sky;
// the same map as OpenEXR and as Radiance HDR renders the same image; a black map renders
// black (no NaN); and `file` may be given with --set like any field.
// The floor y = 0 (albedo a, normal +y) sees the upper hemisphere only, so a pixel's expected
// value is a/pi * E with, for a map of W x H texels (H even: the horizon is a row edge),
//   E = sum over rows r < H/2 and columns of L_rc (2 pi / W) (cos^2 t_r - cos^2 t_r+1) / 2,
// t_r = pi r / H: the integral of cos(theta) over the texel (cos theta = d.y, uniform in phi).
// Tolerances: the block t-test of tests/render_helpers.h at alpha = 1e-3; fixed seeds.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "image/image.h"
#include "render_helpers.h"
#include "rgbe_file.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kAlbedo = 0.6;
constexpr int kSize = 32;
constexpr double kAlpha = 1e-3;
constexpr uint32_t kW = 16, kH = 8;

// A sky: a gradient from the zenith, brighter towards +x, and one bright texel ("sun") at row
// 2, column 5. Values k 2^-n with few bits, exact in RGBE (rgbe_file.h) and in EXR's floats.
std::vector<glm::vec3> skyTexels() {
    std::vector<glm::vec3> t(size_t(kW) * kH);
    for (uint32_t row = 0; row < kH; ++row)
        for (uint32_t col = 0; col < kW; ++col)
            t[size_t(row) * kW + col] = glm::vec3(0.25f + 0.0625f * float(row + (col < kW / 2 ? col : kW - col)), 0.5f,
                                                  0.125f * float(1 + row % 4));
    t[2 * kW + 5] = glm::vec3(48.0f, 40.0f, 24.0f);
    return t;
}

void writeMapExr(const fs::path& path, const std::vector<glm::vec3>& texels) {
    Image image;
    image.width = kW;
    image.height = kH;
    for (glm::vec3 t : texels) image.rgb.insert(image.rgb.end(), {t.x, t.y, t.z});
    writeExr(path, image);
}

// Irradiance at a point of the floor, channel `c`, from texels scaled by `scale`.
double floorIrradiance(const std::vector<glm::vec3>& texels, double scale, int c) {
    double e = 0;
    for (uint32_t row = 0; row < kH / 2; ++row) {
        double c0 = std::cos(kPi * row / kH), c1 = std::cos(kPi * (row + 1) / kH);
        double projected = (2 * kPi / kW) * (c0 * c0 - c1 * c1) / 2;
        for (uint32_t col = 0; col < kW; ++col) e += scale * texels[size_t(row) * kW + col][c] * projected;
    }
    return e;
}

json floorScene(const json& environment, const json& integrator, int spp) {
    return {
        {"camera", test::topDownCamera(0.0, 0.0, 1.5)},
        {"film", {{"width", kSize}, {"height", kSize}}},
        {"sampler", {{"spp", spp}, {"seed", 5}}},
        {"integrator", integrator},
        {"materials", {{"floor", {{"type", "diffuse"}, {"albedo", {kAlbedo, kAlbedo, kAlbedo}}}}}},
        {"shapes", json::array({{{"type", "quad"},
                                 {"origin", {-50, 0, -50}},
                                 {"edge_u", {0, 0, 100}},
                                 {"edge_v", {100, 0, 0}},
                                 {"material", "floor"}}})},
        {"lights", json::array({environment})},
    };
}

json direct(const std::string& strategy) { return {{"type", "direct"}, {"strategy", strategy}}; }

const std::vector<std::string> kStrategies = {"light", "bsdf", "mis", "mixture"};

}  // namespace

TEST(EnvironmentRender, FloorIrradianceIsTheSumOverTexels) {
    std::vector<glm::vec3> texels = skyTexels();
    writeMapExr(test::outputPath("env-sky.exr"), texels);
    const double scale = 2.0;  // `radiance` multiplies the texels
    const double expected = kAlbedo / kPi * floorIrradiance(texels, scale, 0);
    json env = {{"type", "environment"}, {"file", "env-sky.exr"}, {"radiance", {scale, 1, 1}}};
    for (const std::string& strategy : kStrategies) {
        std::string name = "env-floor-" + strategy;
        Image image = test::renderJson(floorScene(env, direct(strategy), 64), name);
        std::vector<double> want(size_t(kSize) * kSize, expected);
        std::string report;
        int failures = test::blockTTest(image, want, 8, kAlpha, int(kStrategies.size()), &report);
        EXPECT_EQ(failures, 0) << strategy << ": expected " << expected << "; " << report;
        if (failures) writeExr(test::outputPath(name + ".exr"), image);
    }
}

TEST(EnvironmentRender, ConstantMapRendersAsTheConstantSky) {
    // A 16 x 8 map of 0.75 everywhere against `radiance` 0.75 without a map: the floor is
    // a * 0.75 under both (E = pi L), and a camera ray that escapes sees 0.75 exactly.
    std::vector<glm::vec3> texels(size_t(kW) * kH, glm::vec3(0.75f));
    writeMapExr(test::outputPath("env-constant.exr"), texels);
    json mapped = {{"type", "environment"}, {"file", "env-constant.exr"}};
    json constant = {{"type", "environment"}, {"radiance", 0.75}};
    for (const json& env : {mapped, constant}) {
        std::string name = env.contains("file") ? "env-constant-map" : "env-constant-sky";
        for (const std::string& strategy : kStrategies) {
            Image image = test::renderJson(floorScene(env, direct(strategy), 32), name + "-" + strategy);
            std::vector<double> want(size_t(kSize) * kSize, kAlbedo * 0.75);
            // Cosine-weighted samples of a constant sky carry a L exactly, up to float
            // rounding (zero variance, where a t-test would weigh rounding alone): every
            // pixel within 1e-5 relative, or, where samples vary, the block t-test.
            size_t off = 0;
            for (size_t p = 0; p < want.size(); ++p) off += std::abs(image.rgb[3 * p] - want[p]) > 1e-5 * want[p];
            std::string report;
            if (off > 0) {
                EXPECT_EQ(test::blockTTest(image, want, 8, kAlpha, 2 * int(kStrategies.size()), &report), 0)
                    << name << " " << strategy << ": " << report;
            }
        }
        // A camera looking up, away from the floor: every ray escapes and sees the sky.
        json sky = floorScene(env, direct("mis"), 1);
        sky["camera"] = {{"eye", {0, 1, 0}}, {"target", {0, 2, -1}}, {"fov_y", 30}};
        Image image = test::renderJson(sky, name + "-background");
        for (size_t i = 0; i < image.rgb.size(); ++i) ASSERT_EQ(image.rgb[i], 0.75f) << name << " value " << i;
    }
}

TEST(EnvironmentRender, ExrAndHdrOfTheSameMapRenderTheSame) {
    std::vector<glm::vec3> texels = skyTexels();
    writeMapExr(test::outputPath("env-same.exr"), texels);
    test::writeRgbeHdr(test::outputPath("env-same.hdr"), kW, kH, texels);
    json doc = floorScene({{"type", "environment"}, {"file", "env-same.exr"}}, direct("mis"), 8);
    // Half the view is the sky, so the lookup is compared as well as the lighting.
    doc["camera"] = {{"eye", {0, 1, 0}}, {"target", {0, 1.2, -1}}, {"fov_y", 60}};
    Image exr = test::renderJson(doc, "env-same-exr");
    doc["lights"][0]["file"] = "env-same.hdr";
    Image hdr = test::renderJson(doc, "env-same-hdr");
    ASSERT_EQ(exr.rgb.size(), hdr.rgb.size());
    size_t differ = 0;
    for (size_t i = 0; i < exr.rgb.size(); ++i) differ += exr.rgb[i] != hdr.rgb[i];
    EXPECT_EQ(differ, 0u);
    double sum = 0;
    for (float v : exr.rgb) sum += v;
    EXPECT_GT(sum, 0.0);
}

TEST(EnvironmentRender, BlackMapRendersBlackWithoutNaN) {
    std::vector<glm::vec3> texels(size_t(kW) * kH, glm::vec3(0.0f));
    writeMapExr(test::outputPath("env-black.exr"), texels);
    json env = {{"type", "environment"}, {"file", "env-black.exr"}};
    for (const std::string& strategy : kStrategies) {
        json doc = floorScene(env, direct(strategy), 4);
        doc["camera"] = {{"eye", {0, 1, 0}}, {"target", {0, 1.2, -1}}, {"fov_y", 60}};
        Image image = test::renderJson(doc, "env-black-" + strategy);
        for (size_t i = 0; i < image.rgb.size(); ++i) ASSERT_EQ(image.rgb[i], 0.0f) << strategy << " value " << i;
    }
}
