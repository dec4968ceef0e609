// Light selection "bvh" in the direct integrator against closed forms: many point lights of
// powers over four decades above a diffuse plane (the exact image is a sum over the lights)
// rendered under uniform, power and bvh selection; an emitting mesh beside them, whose
// triangles the tree chooses one by one, under bvh with MIS, where the BRDF-sampled rays
// that hit a triangle are weighted with the tree's replayed probability of that triangle: a
// wrong one biases the image. Per-sample variances are unknown, so a block t-test of the
// residuals (render_helpers.h) checks each image; its level is derived from the sample
// count through the t distribution, with fixed seeds.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "many_light_scenes.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr double kAlbedo = 0.6;
constexpr double kAlpha = 1e-3;
constexpr double kHalf = 3.0;  // the camera sees [-3, 3]^2 of the plane

json planeScene(int spp, const std::vector<test::PointLight>& points) {
    json doc = test::diffusePlaneScene(spp, 5, 0.0, kHalf, kAlbedo);
    test::addPointLights(doc, points);
    return doc;
}

// Radiance of the plane at x from the point lights: a/pi times their irradiance.
double pointRadiance(const std::vector<test::PointLight>& lights, glm::dvec3 x) {
    return kAlbedo / M_PI * test::pointLightsIrradiance(lights, x);
}

json direct(const std::string& strategy, const std::string& selection, const json& extra = json::object()) {
    json j = {{"type", "direct"}, {"strategy", strategy}, {"light_selection", selection}};
    j.update(extra);
    return j;
}

}  // namespace

TEST(LightBvhRender, ManyPointLightsUnderUniformPowerAndBvh) {
    const std::vector<test::PointLight> lights = test::randomPointLights(64, 21);
    const json doc = planeScene(64, lights);
    test::expectTopDownMatches(
        doc,
        {direct("light", "uniform"), direct("light", "power"), direct("light", "bvh"), direct("mis", "bvh"),
         direct("light", "bvh", {{"light_samples", 3}})},
        [&](glm::dvec3 x) { return pointRadiance(lights, x); }, "bvh-points", kAlpha);
}

// A downward-facing emitting square of 8 triangles (each its own item in the tree) at height
// 2.2, above the point lights (so that it shadows none) and beside the camera's view: MIS (both heuristics, both triangle
// samplings) and light sampling under bvh, and MIS under power for comparison.
TEST(LightBvhRender, MeshLightWithMisUnderBvh) {
    const std::vector<test::PointLight> lights = test::randomPointLights(12, 22);
    json doc = planeScene(128, lights);
    const double Le = 3.0, h = 2.2;
    const std::vector<glm::dvec3> outline = test::addEmittingSquareMesh(doc, Le, h);
    test::expectTopDownMatches(
        doc,
        {direct("mis", "bvh"), direct("mis", "bvh", {{"heuristic", "balance"}}), direct("light", "bvh"),
         direct("mis", "bvh", {{"triangle_sampling", "solid_angle"}}), direct("mis", "power")},
        [&](glm::dvec3 x) {
            return pointRadiance(lights, x) + kAlbedo / M_PI * test::polygonIrradiance(outline, x, Le);
        },
        "bvh-mesh", kAlpha);
}
