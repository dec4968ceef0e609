// The direct kernel that reads nodes through their address traces each sample's camera ray
// together with the previous sample's first shadow ray and, where BRDF-sampled rays find
// their emitter first, the last BRDF sample's query for occluders (integrators/direct.comp,
// addPixelSamples; geometry/bvh.glsl, tracePair). A sample's value must not depend on that:
// whatever the strategy and the way BRDF-sampled rays find emitters, and however a render's
// samples are split into dispatches (so that a sample's shadow rays go with another camera
// ray, or with none), the image is the one of the kernels that trace one ray at a time, bit
// for bit.
// (tests/test_bvh.cpp checks tracePair's hits against brute force.)
#include <gtest/gtest.h>

#include <string>

#include "gpu_fixture.h"
#include "render/renderer.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;

namespace {

// A lit floor (test_scenes.h) with spheres that shadow part of it and a point light beside
// the quad light, so that light samples are delta and area ones, blocked and not.
json pairsScene(const json& integrator) {
    json doc = test::litFloorOnOddFilmScene(5, 9);
    doc["integrator"] = integrator;
    for (int i = 0; i < 24; ++i)
        doc["shapes"].push_back({{"type", "sphere"},
                                 {"center", {-0.9 + 0.075 * i, 0.1 + 0.05 * (i % 4), 0.05 * i - 0.6}},
                                 {"radius", 0.05 + 0.02 * (i % 5)}});
    doc["lights"] = {{{"type", "point"}, {"position", {1, 1.5, 1}}, {"power", 8}}};
    return doc;
}

// The scene through the BVH with nodes read as `reads`, BRDF-sampled rays finding emitters
// as `emitterFirst` says, in submissions of at most `maxPixelSamples` pixel samples (0: as
// the time allows, here the whole render at once).
Image render(const Scene& scene, NodeReads reads, EmitterFirst emitterFirst, uint64_t maxPixelSamples) {
    Renderer renderer(test::gpuContext(), scene);
    renderer.setInlineGeometry(InlineGeometry::Off);
    renderer.setNodeReads(reads);
    renderer.setEmitterFirst(emitterFirst);
    renderer.renderAll({}, nullptr, RenderPacing{1.0, maxPixelSamples});
    return renderer.readback(0.0);
}

size_t differingValues(const Image& a, const Image& b) {
    if (a.rgb.size() != b.rgb.size()) return SIZE_MAX;
    size_t differing = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) differing += a.rgb[i] != b.rgb[i];
    return differing;
}

}  // namespace

TEST(TracePairs, ASampleIsTheSameWhicheverRayItsShadowRayGoesWith) {
    ASSERT_TRUE(test::gpuContext().info().shaderInt64 && test::gpuContext().info().bufferDeviceAddress)
        << "the test device should read nodes through their address";
    // Every strategy: mis and light leave their first light sample's shadow ray to the next
    // sample's iteration (with three light samples, the other two are traced at once), and
    // mis with emitters found first its last BRDF sample's query for occluders too; bsdf and
    // mixture trace theirs at once and leave none.
    // EmitterFirst::Rule decides by the scene, so mis is also run with the path forced.
    const std::pair<json, EmitterFirst> integrators[] = {
        {{{"type", "direct"}, {"strategy", "mis"}}, EmitterFirst::Rule},
        {{{"type", "direct"}, {"strategy", "mis"}}, EmitterFirst::Exact},
        {{{"type", "direct"}, {"strategy", "mis"}, {"light_samples", 2}, {"bsdf_samples", 3}}, EmitterFirst::Exact},
        {{{"type", "direct"}, {"strategy", "light"}, {"light_samples", 3}}, EmitterFirst::Rule},
        {{{"type", "direct"}, {"strategy", "bsdf"}}, EmitterFirst::Rule},
        {{{"type", "direct"}, {"strategy", "mixture"}, {"light_samples", 2}, {"bsdf_samples", 2}}, EmitterFirst::Rule},
    };
    for (const auto& [integrator, emitterFirst] : integrators) {
        SCOPED_TRACE(integrator.dump() + (emitterFirst == EmitterFirst::Exact ? ", emitters first" : ""));
        const Scene scene = test::sceneFromJson(pairsScene(integrator), "trace-pairs");
        const Image single = render(scene, NodeReads::Texels, emitterFirst, 0);
        size_t dark = 0;
        for (float v : single.rgb) dark += v == 0.0f;
        EXPECT_LT(dark, single.rgb.size() / 2) << "the floor should be lit";
        EXPECT_EQ(differingValues(render(scene, NodeReads::Address, emitterFirst, 0), single), 0u);
        // Submissions of less than a row (36 of 37 pixels): no sweeps, so every dispatch
        // adds one sample per pixel, and its shadow rays are traced with no camera ray.
        // Then bands that split passes at odd places, and sweeps of several samples per
        // dispatch.
        for (uint64_t maxPixelSamples : {uint64_t(36), uint64_t(37 * 3 + 5), uint64_t(37 * 35 * 2 + 11)})
            EXPECT_EQ(differingValues(render(scene, NodeReads::Address, emitterFirst, maxPixelSamples), single), 0u)
                << "at most " << maxPixelSamples << " pixel samples per submission";
    }
}

// The test above compares the waiting BRDF queries only where the emitter-first path is
// taken: it is, for mis on that scene, since fewer rays are traced with it than without.
TEST(TracePairs, TheEmitterFirstPathIsTakenInThatScene) {
    const Scene scene = test::sceneFromJson(pairsScene({{"type", "direct"}, {"strategy", "mis"}}), "trace-pairs");
    uint64_t rays[2];
    for (int i = 0; i < 2; ++i) {
        Renderer renderer(test::gpuContext(), scene);
        renderer.setInlineGeometry(InlineGeometry::Off);
        renderer.setNodeReads(NodeReads::Address);
        renderer.setEmitterFirst(i == 0 ? EmitterFirst::Off : EmitterFirst::Exact);
        rays[i] = renderer.countRays(2);
    }
    EXPECT_GT(rays[1], 0u);
    EXPECT_LT(rays[1], rays[0]);
}
