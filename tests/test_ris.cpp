// Strategy "ris" (integrators/ris.glsl) against the closed forms the other strategies are
// tested on, viewed top-down on a diffuse plane y = 0 of albedo a:
//   quad light     a/pi * Le/2 |sum_i Theta_i (Gamma_i . n)|        (Lambert; Arvo 1995)
//   sphere light   a/pi * pi Le (r/d)^2 cos(theta)
//   point lights   a/pi * sum_l I_l cos(theta_l) / d_l^2             (an exact sum)
//   mesh light     the polygon formula over its outline, plus point lights beside it, so
//                  that delta and area candidates share one sum of weights
// under power and bvh light selection, with and without BRDF candidates, and RIS agreeing
// with mis on glossy Phong plates (no closed form: a block t-test of the difference of
// independent renders). Per-sample variances are unknown, so a block t-test of the
// residuals (render_helpers.h) checks each image at level 1e-3 over all of its blocks, the
// tolerance following from the sample count through the t distribution, with fixed seeds.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "image/image.h"
#include "many_light_scenes.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr double kAlbedo = 0.6;
constexpr double kAlpha = 1e-3;

json planeScene(int spp, double cx, double half) { return test::diffusePlaneScene(spp, 17, cx, half, kAlbedo); }

json ris(const std::string& selection = "power", const json& extra = json::object()) {
    json j = {{"type", "direct"}, {"strategy", "ris"}, {"light_selection", selection}};
    j.update(extra);
    return j;
}

double pointRadiance(const std::vector<test::PointLight>& lights, glm::dvec3 x) {
    return kAlbedo / M_PI * test::pointLightsIrradiance(lights, x);
}

}  // namespace

TEST(RisClosedForm, QuadLight) {
    const double Le = 5.0, h = 1.5;
    json doc = planeScene(128, 3.0, 1.5);
    doc["shapes"].push_back({{"type", "quad"},
                             {"origin", {-0.5, h, -0.5}},
                             {"edge_u", {1, 0, 0}},
                             {"edge_v", {0, 0, 1}},
                             {"emission", {Le, Le, Le}},
                             {"material", "black"}});
    const std::vector<glm::dvec3> quad = {{-0.5, h, -0.5}, {0.5, h, -0.5}, {0.5, h, 0.5}, {-0.5, h, 0.5}};
    test::expectTopDownMatches(
        doc,
        {ris(), ris("power", {{"quad_sampling", "area"}}), ris("power", {{"bsdf_samples", 0}}),
         ris("power", {{"ris_candidates", 1}, {"bsdf_samples", 3}}), ris("power", {{"light_samples", 2}}), ris("bvh")},
        [&](glm::dvec3 x) { return kAlbedo / M_PI * test::polygonIrradiance(quad, x, Le); }, "ris-quad", kAlpha);
}

TEST(RisClosedForm, SphereLight) {
    const double Le = 4.0, r = 0.4, h = 1.5;
    json doc = planeScene(128, 3.0, 1.5);
    doc["shapes"].push_back(
        {{"type", "sphere"}, {"center", {0, h, 0}}, {"radius", r}, {"emission", {Le, Le, Le}}, {"material", "black"}});
    test::expectTopDownMatches(
        doc, {ris(), ris("power", {{"sphere_sampling", "area"}}), ris("bvh", {{"ris_candidates", 3}})},
        [&](glm::dvec3 x) {
            double d2 = x.x * x.x + x.z * x.z + h * h;
            return kAlbedo / M_PI * M_PI * Le * r * r / d2 * (h / std::sqrt(d2));
        },
        "ris-sphere", kAlpha);
}

// Delta lights alone: every candidate is a point light, whose density is its selection pmf.
TEST(RisClosedForm, ManyPointLightsUnderPowerAndBvh) {
    const std::vector<test::PointLight> lights = test::randomPointLights(64, 21);
    json doc = planeScene(64, 0.0, 3.0);
    test::addPointLights(doc, lights);
    test::expectTopDownMatches(
        doc, {ris("power"), ris("bvh"), ris("uniform"), ris("bvh", {{"ris_candidates", 2}, {"light_samples", 2}})},
        [&](glm::dvec3 x) { return pointRadiance(lights, x); }, "ris-points", kAlpha);
}

// An emitting square of 8 triangles (a mesh light, each triangle its own item under bvh) at
// height 2.2, above the point lights (so that it shadows none) and beside the camera's view: area candidates, whose MIS denominator has a BRDF term, and delta candidates,
// whose has none, compete in one reservoir.
TEST(RisClosedForm, MeshLightBesidePointLights) {
    const std::vector<test::PointLight> lights = test::randomPointLights(12, 22);
    json doc = planeScene(128, 0.0, 3.0);
    test::addPointLights(doc, lights);
    const double Le = 3.0, h = 2.2;
    const std::vector<glm::dvec3> outline = test::addEmittingSquareMesh(doc, Le, h);
    test::expectTopDownMatches(
        doc, {ris("power"), ris("bvh"), ris("bvh", {{"triangle_sampling", "solid_angle"}, {"bsdf_samples", 2}})},
        [&](glm::dvec3 x) {
            return pointRadiance(lights, x) + kAlbedo / M_PI * test::polygonIrradiance(outline, x, Le);
        },
        "ris-mesh", kAlpha);
}

namespace {

std::vector<double> channel0(const Image& image) {
    std::vector<double> out(size_t(image.width) * image.height);
    for (size_t p = 0; p < out.size(); ++p) out[p] = image.rgb[3 * p];
    return out;
}

}  // namespace

// Independent renders (different seeds) of ris must agree with mis: the difference image has
// mean zero (block t-test on the difference), where glossy lobes make the BRDF candidates count.
TEST(RisConsistency, AgreesWithMisOnGlossyPlates) {
    const int spp = 256;
    const Image mis =
        test::renderJson(test::glossyPlatesScene(spp, 1, {{"type", "direct"}, {"strategy", "mis"}}), "ris-glossy-mis");
    const std::vector<json> others = {ris("power"), ris("bvh"),
                                      ris("power", {{"bsdf_samples", 2}, {"ris_candidates", 4}})};
    for (size_t i = 0; i < others.size(); ++i) {
        const std::string name = "ris-glossy-" + std::to_string(i);
        Image image = test::renderJson(test::glossyPlatesScene(spp, 2 + uint32_t(i), others[i]), name);
        std::string report;
        EXPECT_EQ(test::blockTTest(image, channel0(mis), 8, kAlpha, int(others.size()), &report), 0)
            << others[i].dump() << ": " << report;
        if (::testing::Test::HasFailure()) writeExr(test::outputPath(name + ".exr"), image);
    }
}
