// Light selection "bvh" in the direct integrator against closed forms: many point lights of
// powers over four decades above a diffuse plane (the exact image is a sum over the lights)
// rendered under uniform, power and bvh selection; an emitting mesh beside them, whose
// triangles the tree chooses one by one, under bvh with MIS, where the BRDF-sampled rays
// that hit a triangle are weighted with the tree's replayed probability of that triangle: a
// wrong one biases the image. Per-sample variances are unknown, so a block t-test of the
// residuals (render_helpers.h) checks each image; its level is derived from the sample
// count through the t distribution, with fixed seeds.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr double kAlbedo = 0.6;
constexpr int kSize = 32;
constexpr double kAlpha = 1e-3;
constexpr double kHalf = 3.0;  // the camera sees [-3, 3]^2 of the plane

struct PointLight {
    glm::dvec3 position;
    double intensity;
};

// `count` point lights over [-4, 4]^2 at heights 0.5 to 2, intensities 0.01 to 100 W/sr.
std::vector<PointLight> pointLights(int count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<PointLight> lights;
    for (int i = 0; i < count; ++i)
        lights.push_back(
            {{8.0 * u(rng) - 4.0, 0.5 + 1.5 * u(rng), 8.0 * u(rng) - 4.0}, 0.01 * std::pow(10.0, 4.0 * u(rng))});
    return lights;
}

json planeScene(int spp, const std::vector<PointLight>& points) {
    json lights = json::array();
    for (const PointLight& l : points)
        lights.push_back({{"type", "point"},
                          {"position", {l.position.x, l.position.y, l.position.z}},
                          {"intensity", {l.intensity, l.intensity, l.intensity}}});
    return {
        {"camera", test::topDownCamera(0.0, 0.0, kHalf)},
        {"film", {{"width", kSize}, {"height", kSize}}},
        {"sampler", {{"spp", spp}, {"seed", 5}}},
        {"materials",
         {{"plane", {{"type", "diffuse"}, {"albedo", {kAlbedo, kAlbedo, kAlbedo}}}},
          {"black", {{"type", "diffuse"}, {"albedo", {0, 0, 0}}}}}},
        {"shapes", json::array({{{"type", "quad"},
                                 {"origin", {-50, 0, -50}},
                                 {"edge_u", {0, 0, 100}},
                                 {"edge_v", {100, 0, 0}},
                                 {"material", "plane"}}})},
        {"lights", lights},
    };
}

// Radiance of the plane at x from the point lights: a/pi sum I cos(theta) / d^2.
double pointRadiance(const std::vector<PointLight>& lights, glm::dvec3 x) {
    double sum = 0.0;
    for (const PointLight& l : lights) {
        glm::dvec3 d = l.position - x;
        double d2 = glm::dot(d, d);
        sum += l.intensity * (d.y / std::sqrt(d2)) / d2;
    }
    return kAlbedo / M_PI * sum;
}

json direct(const std::string& strategy, const std::string& selection, const json& extra = json::object()) {
    json j = {{"type", "direct"}, {"strategy", strategy}, {"light_selection", selection}};
    j.update(extra);
    return j;
}

}  // namespace

TEST(LightBvhRender, ManyPointLightsUnderUniformPowerAndBvh) {
    const std::vector<PointLight> lights = pointLights(64, 21);
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
    const std::vector<PointLight> lights = pointLights(12, 22);
    json doc = planeScene(128, lights);
    const double Le = 3.0, h = 2.2;
    // A 2 x 2 grid of squares over [-2, 2] x [3.5, 7.5], two triangles each, counter-clockwise seen
    // from below (their front faces the plane).
    json positions = json::array(), indices = json::array();
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 2; ++i) positions.insert(positions.end(), {-2.0 + 2.0 * i, h, 3.5 + 2.0 * j});
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            int a = j * 3 + i, b = a + 1, c = a + 3, d = a + 4;
            indices.insert(indices.end(), {a, b, c, b, d, c});
        }
    doc["shapes"].push_back({{"type", "mesh"},
                             {"positions", positions},
                             {"indices", indices},
                             {"emission", {Le, Le, Le}},
                             {"material", "black"}});
    const std::vector<glm::dvec3> outline = {{-2, h, 3.5}, {2, h, 3.5}, {2, h, 7.5}, {-2, h, 7.5}};
    test::expectTopDownMatches(
        doc,
        {direct("mis", "bvh"), direct("mis", "bvh", {{"heuristic", "balance"}}), direct("light", "bvh"),
         direct("mis", "bvh", {{"triangle_sampling", "solid_angle"}}), direct("mis", "power")},
        [&](glm::dvec3 x) {
            return pointRadiance(lights, x) + kAlbedo / M_PI * test::polygonIrradiance(outline, x, Le);
        },
        "bvh-mesh", kAlpha);
}
