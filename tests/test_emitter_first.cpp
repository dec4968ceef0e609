// Emitter-first BRDF-sampled rays (shaders/integrators/emitter_first.glsl): where the host's
// rule turns them on (render/emitter_first.cpp), and that they are the same estimator as the
// closest-hit path. The scenes put an occluder between the emitters and the floor, so that
// a BRDF-sampled ray often finds an emitter behind something: a path that let such a ray
// through, or hid an emitter behind itself, would brighten or darken the shadow.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "render/emitter_first.h"
#include "render/kernel_options.h"
#include "render/renderer.h"
#include "render_helpers.h"
#include "scene/load.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr int kSize = 32;

// A closed room 4 x 3 x 4 (so that every BRDF-sampled ray hits something, as in the scenes
// the rule takes) seen from under its ceiling: a one-sided quad light facing down just below
// the ceiling, a blocker quad at half height under part of the light (its shadow crosses
// the view), a point light (a delta light the emitter loop must skip) and, with `sphere`, a
// sphere light between blocker and quad light, which hides part of the quad light.
// With `open`, only the floor, blocker and lights: most rays leave the scene.
json occludedScene(const std::string& strategy, int spp, int seed, bool sphere, bool open = false) {
    auto quad = [](json origin, json u, json v) {
        return json{{"type", "quad"}, {"origin", origin}, {"edge_u", u}, {"edge_v", v}, {"material", "walls"}};
    };
    json shapes = json::array({quad({-2, 0, -2}, {0, 0, 4}, {4, 0, 0}),
                               quad({-0.1, 1.5, -1}, {2, 0, 0}, {0, 0, 2}),
                               {{"type", "quad"},
                                {"origin", {-0.3, 2.9, -0.3}},
                                {"edge_u", {0.6, 0, 0}},
                                {"edge_v", {0, 0, 0.6}},
                                {"emission", {8, 8, 8}}}});
    if (!open)
        for (const json& wall : {quad({-2, 3, -2}, {4, 0, 0}, {0, 0, 4}), quad({-2, 0, -2}, {0, 3, 0}, {0, 0, 4}),
                                 quad({2, 0, -2}, {0, 3, 0}, {0, 0, 4}), quad({-2, 0, -2}, {4, 0, 0}, {0, 3, 0}),
                                 quad({-2, 0, 2}, {4, 0, 0}, {0, 3, 0})})
            shapes.push_back(wall);
    if (sphere)
        shapes.push_back({{"type", "sphere"}, {"center", {-0.2, 2.3, 0}}, {"radius", 0.2}, {"emission", {3, 2, 1}}});
    return {
        {"camera", {{"eye", {0, 2.7, 1.9}}, {"target", {0, 0, -0.5}}, {"up", {0, 1, 0}}, {"fov_y", 70}}},
        {"film", {{"width", kSize}, {"height", kSize}}},
        {"sampler", {{"spp", spp}, {"seed", seed}}},
        {"integrator", {{"type", "direct"}, {"strategy", strategy}}},
        {"materials",
         {{"walls", {{"type", "phong"}, {"kd", {0.5, 0.5, 0.5}}, {"ks", {0.3, 0.3, 0.3}}, {"exponent", 8}}}}},
        {"shapes", shapes},
        {"lights", {{{"type", "point"}, {"position", {1.5, 1.0, 1.5}}, {"power", 2}}}},
    };
}

// The open scene with its floor a bumpy grid of 2 x 256 x 256 triangles.
json openSceneOnDenseMesh() {
    json doc = occludedScene("mis", 1, 1, false, true);
    constexpr int n = 256;
    json positions = json::array(), indices = json::array();
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            double x = -2.0 + 4.0 * i / n, z = -2.0 + 4.0 * j / n;
            positions.insert(positions.end(), {x, 0.02 * std::sin(9.0 * x) * std::cos(7.0 * z), z});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            indices.insert(indices.end(), {a, c, b, b, c, d});
        }
    doc["shapes"][0] = {{"type", "mesh"}, {"positions", positions}, {"indices", indices}, {"material", "walls"}};
    return doc;
}

// Rendered with the BVH: the rule weighs the emitter-first path against the BVH's closest
// hit, and these rooms are small enough to go inline otherwise (render/inline_geometry.h).
Image render(const json& doc, const std::string& name, EmitterFirst mode, KernelOptions* options = nullptr) {
    Scene scene = test::sceneFromJson(doc, name);
    Renderer renderer(test::gpuContext(), scene);
    renderer.setEmitterFirst(mode);
    renderer.setInlineGeometry(InlineGeometry::Off);
    if (options) *options = makeKernelOptions(scene, renderer.arrays(), mode, InlineGeometry::Off);
    renderer.renderAll();
    return renderer.readback(0.0);
}

// Channel 0 of an image as the "expected" values of test::blockTTest.
std::vector<double> channel0(const Image& image) {
    std::vector<double> v;
    for (size_t i = 0; i < image.rgb.size(); i += 3) v.push_back(image.rgb[i]);
    return v;
}

}  // namespace

TEST(EmitterFirst, RuleTakesTheScenesItWasMeasuredOn) {
    auto pays = [](const json& doc, const std::string& name) {
        Scene scene = test::sceneFromJson(doc, name);
        return emitterFirstPays(scene, buildSceneArrays(scene));
    };
    EXPECT_TRUE(pays(occludedScene("mis", 1, 1, false), "ef-rule-quad"));
    EXPECT_TRUE(pays(occludedScene("bsdf", 1, 1, false), "ef-rule-bsdf"));
    // Most rays leave an open scene, cheaply for the closest hit: measured to lose.
    EXPECT_FALSE(pays(occludedScene("mis", 1, 1, false, true), "ef-rule-open"));
    // Unless the surfaces the rays leave from are dense meshes: then even a ray that leaves
    // the scene descends through a deep tree around its origin, which the path saves.
    EXPECT_TRUE(pays(openSceneOnDenseMesh(), "ef-rule-dense"));
    // Light sampling alone traces no BRDF-sampled ray: nothing to gain.
    EXPECT_FALSE(pays(occludedScene("light", 1, 1, false), "ef-rule-light"));
    // An environment is hit by every escaping ray; a mesh emitter is no sphere or quad.
    json env = occludedScene("mis", 1, 1, false);
    env["lights"].push_back({{"type", "environment"}, {"radiance", 0.1}});
    EXPECT_FALSE(pays(env, "ef-rule-env"));
    json mesh = occludedScene("mis", 1, 1, false);
    mesh["shapes"][2] = {{"type", "mesh"},
                         {"positions", {-0.5, 2, -0.5, 0.5, 2, -0.5, 0.5, 2, 0.5}},
                         {"indices", {0, 1, 2}},
                         {"emission", {4, 4, 4}}};
    EXPECT_FALSE(pays(mesh, "ef-rule-mesh"));
    // Ambient occlusion has no emitters to look for.
    json ao = occludedScene("mis", 1, 1, false);
    ao["integrator"] = {{"type", "ao"}};
    EXPECT_FALSE(pays(ao, "ef-rule-ao"));
}

// A diffuse room of six quads, 8 x 4 x 8, lit by three sphere lights of radii 0.08, 0.3 and
// 0.6 (build/bench/sphere_room.json, tools/scenes/make_bench_scenes.py, scaled up): few of its
// BRDF-sampled rays find an emitter (about 4%), so the BVH scenes' rule takes it.
json largeSphereRoom() {
    auto quad = [](json origin, json u, json v) {
        return json{{"type", "quad"}, {"origin", origin}, {"edge_u", u}, {"edge_v", v}, {"material", "white"}};
    };
    json shapes = json::array({quad({-4, 0, -4}, {0, 0, 8}, {8, 0, 0}), quad({-4, 4, -4}, {8, 0, 0}, {0, 0, 8}),
                               quad({-4, 0, -4}, {8, 0, 0}, {0, 4, 0}), quad({-4, 0, -4}, {0, 4, 0}, {0, 0, 8}),
                               quad({4, 0, -4}, {0, 0, 8}, {0, 4, 0}), quad({-4, 0, 4}, {0, 4, 0}, {8, 0, 0})});
    for (const auto& [center, radius] : std::vector<std::pair<json, double>>{
             {{-2.4, 2.9, -2.0}, 0.08}, {{1.8, 2.1, -1.2}, 0.3}, {{-0.4, 0.8, -1.8}, 0.6}})
        shapes.push_back({{"type", "sphere"}, {"center", center}, {"radius", radius}, {"emission", {5, 5, 5}}});
    return {
        {"camera", {{"eye", {0, 1.8, 3.8}}, {"target", {0, 1.2, -1}}, {"up", {0, 1, 0}}, {"fov_y", 60}}},
        {"film", {{"width", kSize}, {"height", kSize}}},
        {"integrator", {{"type", "direct"}}},
        {"materials", {{"white", {{"type", "diffuse"}, {"albedo", {0.73, 0.73, 0.73}}}}}},
        {"shapes", shapes},
    };
}

// The inline scenes' rule, at the scenes its constants were fitted to (docs/performance-history/round-29.md;
// BrdfRayFates::emitter, lights, primitives): where callgrind counted fewer
// instructions per sample with the path, and where it counted more.
TEST(EmitterFirst, InlineRuleWeighsTheLightLoopAgainstTheClosestHit) {
    EXPECT_TRUE(emitterFirstPaysInline(0.009, 1, 30));  // Cornell box, one quad light: 0.85x
    EXPECT_TRUE(emitterFirstPaysInline(0.015, 1, 8));   // room, one sphere light: 0.98x
    EXPECT_FALSE(emitterFirstPaysInline(0.038, 3, 9));  // large room, three sphere lights: 1.12x
    EXPECT_FALSE(emitterFirstPaysInline(0.097, 3, 9));  // the bench's sphere room: 1.16x
    EXPECT_FALSE(emitterFirstPaysInline(0.5, 1, 40));   // most groups find an emitter: nothing saved
}

// The kernel a scene gets follows the rule of its geometry: the large sphere room goes
// inline, where the path loses, though the BVH's rule would take it.
TEST(EmitterFirst, InlineSceneGetsTheInlineRule) {
    Scene scene = test::sceneFromJson(largeSphereRoom(), "ef-inline-room");
    SceneArrays arrays = buildSceneArrays(scene);
    ASSERT_TRUE(emitterFirstPays(scene, arrays));
    KernelOptions inlined = makeKernelOptions(scene, arrays, EmitterFirst::Rule, InlineGeometry::Rule);
    ASSERT_GT(inlined.inlineGeometry.slotCount(), 0u);
    EXPECT_EQ(inlined.emitterFirstLights, 0u);
    // Through the BVH the BVH's rule still decides.
    EXPECT_EQ(makeKernelOptions(scene, arrays, EmitterFirst::Rule, InlineGeometry::Off).emitterFirstLights,
              uint32_t(arrays.lights.size()));
    // And the Cornell box, inline, keeps the path.
    Scene cornell = loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell.json");
    SceneArrays cornellArrays = buildSceneArrays(cornell);
    KernelOptions cornellOptions = makeKernelOptions(cornell, cornellArrays, EmitterFirst::Rule, InlineGeometry::Rule);
    ASSERT_GT(cornellOptions.inlineGeometry.slotCount(), 0u);
    EXPECT_GT(cornellOptions.emitterFirstLights, 0u);
}

TEST(EmitterFirst, SameSamplesGiveTheSameImageAsTheClosestHit) {
    // Same seed, same random numbers: every BRDF-sampled ray is the same ray on both paths,
    // so the images agree to rounding wherever the estimators agree. With two emitters the
    // nearer must hide the farther (the sphere case, taken with EmitterFirst::Exact). Each
    // strategy weighs BRDF-sampled rays its own way (alone, MIS, mixture density).
    const std::pair<std::string, bool> cases[] = {{"bsdf", false}, {"mixture", false}, {"mis", true}};
    for (const auto& [strategy, sphere] : cases) {
        SCOPED_TRACE(strategy + (sphere ? " with the sphere light" : ""));
        const json doc = occludedScene(strategy, 16, 7, sphere);
        const std::string name = "ef-same-" + strategy + (sphere ? "-sphere" : "");
        KernelOptions on;
        Image first = render(doc, name, EmitterFirst::Exact, &on);
        ASSERT_GT(on.emitterFirstLights, 0u);
        Image closest = render(doc, name, EmitterFirst::Off);
        ASSERT_EQ(first.rgb.size(), closest.rgb.size());
        int differing = 0;
        double worst = 0;
        for (size_t i = 0; i < first.rgb.size(); ++i) {
            double d = std::abs(double(first.rgb[i]) - double(closest.rgb[i]));
            worst = std::max(worst, d);
            differing += d > 1e-4 * (1.0 + std::abs(double(closest.rgb[i])));
        }
        EXPECT_EQ(differing, 0) << "largest difference " << worst;
    }
}

TEST(EmitterFirst, IndependentRendersAgreeWithTheClosestHitWithinMonteCarloError) {
    // Different seeds: the per-pixel differences have mean zero if the two paths are the
    // same estimator; test::blockTTest checks that on 8x8 blocks and on the whole image,
    // with the variance estimated from the differences themselves (it shrinks as 1/spp).
    const int spp = 64;
    KernelOptions options;
    Image first = render(occludedScene("bsdf", spp, 3, false), "ef-mc-first", EmitterFirst::Rule, &options);
    ASSERT_GT(options.emitterFirstLights, 0u) << "the rule no longer takes this scene";
    Image closest = render(occludedScene("bsdf", spp, 4, false), "ef-mc-closest", EmitterFirst::Off);
    std::string report;
    EXPECT_EQ(test::blockTTest(first, channel0(closest), 8, 1e-3, 1, &report), 0) << report;
}
