// Inline geometry (shaders/geometry/inline_geometry.glsl, render/inline_geometry.h): which
// scenes the rule puts inline, and that a render with the primitives inline is the same
// render as with the BVH: the same rays find the same primitives at the same distances, so
// with the same samples the images agree to rounding. The scene mixes every primitive kind
// (quads, triangles of a mesh, spheres), emitting and not, and a textured-free Phong
// material whose lobe makes the BRDF-sampled rays find the small lights.
#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/bvh.h"
#include "gpu/shaders.h"
#include "gpu_fixture.h"
#include "render/renderer.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;

namespace {

// A room of quads with a mesh box (12 triangles), a sphere and a sphere light, a quad light
// and a point light: 20 primitives, seen by a 32 x 32 film. `extra` more spheres line
// the back wall, to push the primitive count past the rule's limit.
json mixedRoom(const std::string& strategy, int extra = 0) {
    auto quad = [](json origin, json u, json v) {
        return json{{"type", "quad"}, {"origin", origin}, {"edge_u", u}, {"edge_v", v}, {"material", "walls"}};
    };
    json shapes = json::array({quad({-2, 0, -2}, {0, 0, 4}, {4, 0, 0}), quad({-2, 3, -2}, {4, 0, 0}, {0, 0, 4}),
                               quad({-2, 0, -2}, {0, 3, 0}, {0, 0, 4}), quad({2, 0, -2}, {0, 3, 0}, {0, 0, 4}),
                               quad({-2, 0, -2}, {4, 0, 0}, {0, 3, 0})});
    shapes.push_back({{"type", "quad"},
                      {"origin", {-0.3, 2.9, -0.3}},
                      {"edge_u", {0.6, 0, 0}},
                      {"edge_v", {0, 0, 0.6}},
                      {"emission", {8, 8, 8}}});
    shapes.push_back({{"type", "sphere"}, {"center", {0.8, 0.4, -0.5}}, {"radius", 0.4}, {"material", "walls"}});
    shapes.push_back({{"type", "sphere"}, {"center", {-0.9, 1.8, -0.8}}, {"radius", 0.15}, {"emission", {6, 4, 2}}});
    const double x0 = -1.2, x1 = -0.4, z0 = -0.6, z1 = 0.2, h = 0.9;
    shapes.push_back(
        {{"type", "mesh"},
         {"positions", {x0, 0, z0, x1, 0, z0, x1, 0, z1, x0, 0, z1, x0, h, z0, x1, h, z0, x1, h, z1, x0, h, z1}},
         {"indices",
          {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7}},
         {"material", "walls"}});
    for (int i = 0; i < extra; ++i)
        shapes.push_back({{"type", "sphere"},
                          {"center", {-1.8 + 3.6 * (i + 0.5) / extra, 2.5, -1.9}},
                          {"radius", 0.04},
                          {"material", "walls"}});
    return {
        {"camera", {{"eye", {0, 1.5, 1.9}}, {"target", {0, 0.8, -1}}, {"up", {0, 1, 0}}, {"fov_y", 75}}},
        {"film", {{"width", 32}, {"height", 32}}},
        {"sampler", {{"spp", 16}, {"seed", 3}}},
        {"integrator", {{"type", "direct"}, {"strategy", strategy}}},
        {"materials",
         {{"walls", {{"type", "phong"}, {"kd", {0.5, 0.5, 0.5}}, {"ks", {0.3, 0.3, 0.3}}, {"exponent", 8}}}}},
        {"shapes", shapes},
        {"lights", {{{"type", "point"}, {"position", {1.5, 1.0, 1.5}}, {"power", 2}}}},
    };
}

Image render(const json& doc, const std::string& name, InlineGeometry mode, KernelOptions* options) {
    Scene scene = test::sceneFromJson(doc, name);
    Renderer renderer(test::gpuContext(), scene);
    renderer.setInlineGeometry(mode);
    *options = makeKernelOptions(scene, renderer.arrays(), EmitterFirst::Rule, mode);
    renderer.renderAll();
    return renderer.readback(0.0);
}

size_t primitiveCount(const json& doc, const std::string& name) {
    Scene scene = test::sceneFromJson(doc, name);
    return buildSceneArrays(scene).bvh.primitives.size();
}

}  // namespace

TEST(InlineGeometry, RuleTakesSmallScenesOnly) {
    auto inlined = [](const json& doc, const std::string& name) {
        Scene scene = test::sceneFromJson(doc, name);
        return !makeKernelOptions(scene, buildSceneArrays(scene)).inlineGeometry.slots.empty();
    };
    const json small = mixedRoom("mis");
    ASSERT_EQ(primitiveCount(small, "inline-rule-small"), 20u);
    EXPECT_TRUE(inlined(small, "inline-rule-small"));
    const int limit = int(INLINE_MAX_PRIMITIVES);
    const json atLimit = mixedRoom("mis", limit - 20);
    ASSERT_EQ(primitiveCount(atLimit, "inline-rule-limit"), size_t(limit));
    EXPECT_TRUE(inlined(atLimit, "inline-rule-limit"));
    EXPECT_FALSE(inlined(mixedRoom("mis", limit - 19), "inline-rule-over"));
    // A scene of lights alone has no primitive to put inline (and an empty BVH).
    json empty = mixedRoom("light");
    empty["shapes"] = json::array();
    EXPECT_FALSE(inlined(empty, "inline-rule-empty"));
}

// Every primitive count the rule can put inline has a kernel: the host's capacity is the
// smallest multiple of INLINE_CAPACITY_STEP that holds it, and cmake/EmbedShaders.cmake
// compiled that variant of each kernel that traces.
TEST(InlineGeometry, EveryCountHasAnEmbeddedKernel) {
    for (uint32_t count = 1; count <= uint32_t(INLINE_MAX_PRIMITIVES); ++count) {
        const uint32_t capacity = inlineKernelCapacity(count);
        EXPECT_GE(capacity, count);
        EXPECT_LT(capacity - count, uint32_t(INLINE_CAPACITY_STEP));
        EXPECT_EQ(capacity % INLINE_CAPACITY_STEP, 0u);
        for (const char* kernel : {"integrators/direct", "integrators/ao", "tests/bvh_trace"})
            EXPECT_NO_THROW(shaderCode(std::string(kernel) + "_inline" + std::to_string(capacity))) << count;
    }
    EXPECT_THROW(inlineKernelCapacity(0), std::logic_error);
    EXPECT_THROW(inlineKernelCapacity(INLINE_MAX_PRIMITIVES + 1), std::logic_error);
}

TEST(InlineGeometry, SameSamplesGiveTheSameImageAsTheBvh) {
    for (const std::string strategy : {"mis", "light", "bsdf"}) {
        SCOPED_TRACE(strategy);
        const json doc = mixedRoom(strategy);
        const std::string name = "inline-same-" + strategy;
        KernelOptions inlined, traversed;
        Image a = render(doc, name, InlineGeometry::Rule, &inlined);
        ASSERT_FALSE(inlined.inlineGeometry.slots.empty());
        // BRDF-sampled rays go emitter first here, inline as through the BVH: the emitter
        // must not hide itself in the inline occlusion test (bvh.glsl, traceAnyIgnoring).
        if (strategy != "light") {
            EXPECT_GT(inlined.emitterFirstLights, 0u);
        }
        Image b = render(doc, name, InlineGeometry::Off, &traversed);
        ASSERT_TRUE(traversed.inlineGeometry.slots.empty());
        EXPECT_EQ(traversed.emitterFirstLights, inlined.emitterFirstLights);
        ASSERT_EQ(a.rgb.size(), b.rgb.size());
        int differing = 0, lit = 0;
        double worst = 0;
        for (size_t i = 0; i < a.rgb.size(); ++i) {
            double d = std::abs(double(a.rgb[i]) - double(b.rgb[i]));
            worst = std::max(worst, d);
            differing += d > 1e-4 * (1.0 + std::abs(double(b.rgb[i])));
            lit += b.rgb[i] > 0.0f;
        }
        EXPECT_GT(lit, int(a.rgb.size()) * 9 / 10) << "the room should be lit almost everywhere";
        EXPECT_EQ(differing, 0) << "largest difference " << worst;
    }
}

// Primitives beside the BVH's tree (bvh/bvh.h, Bvh::besideCount), in a render: the room with
// 50 more spheres (70 primitives, past the inline rule and BvhOptions::besideFrom) puts four
// of its walls beside the tree, and the render, which the kernel gets from RenderParams,
// is the render with every primitive in the tree, to rounding.
TEST(InlineGeometry, PrimitivesBesideTheTreeGiveTheSameImage) {
    for (const std::string strategy : {"mis", "ao"}) {
        SCOPED_TRACE(strategy);
        json doc = mixedRoom(strategy == "ao" ? "mis" : strategy, 50);
        if (strategy == "ao") doc["integrator"] = {{"type", "ao"}};
        Scene scene = test::sceneFromJson(doc, "beside-" + strategy);
        BvhOptions nothingBeside;
        nothingBeside.maxBeside = 0;
        Renderer beside(test::gpuContext(), scene), inTree(test::gpuContext(), scene, nullptr, nothingBeside);
        ASSERT_EQ(beside.arrays().bvh.besideCount, 4u);
        ASSERT_EQ(inTree.arrays().bvh.besideCount, 0u);
        beside.renderAll();
        inTree.renderAll();
        const Image a = beside.readback(0.0), b = inTree.readback(0.0);
        ASSERT_EQ(a.rgb.size(), b.rgb.size());
        int differing = 0, lit = 0;
        for (size_t i = 0; i < a.rgb.size(); ++i) {
            differing += std::abs(double(a.rgb[i]) - double(b.rgb[i])) > 1e-4 * (1.0 + std::abs(double(b.rgb[i])));
            lit += b.rgb[i] > 0.0f;
        }
        EXPECT_GT(lit, int(a.rgb.size()) * 9 / 10) << "the room should be lit almost everywhere";
        EXPECT_EQ(differing, 0);
    }
}

// Also for each kernel capacity (integrators/ao_inline16, 32 and 48): 8, 20 and 48 primitives.
TEST(InlineGeometry, AmbientOcclusionSameSamplesSameImage) {
    std::vector<uint32_t> capacities;
    for (const int extra : {-12, 0, int(INLINE_MAX_PRIMITIVES) - 20}) {
        json doc = mixedRoom("mis", std::max(extra, 0));
        if (extra < 0) doc["shapes"].erase(8);  // the mesh box: 12 triangles
        doc["integrator"] = {{"type", "ao"}};
        const std::string name = "inline-same-ao" + std::to_string(extra);
        SCOPED_TRACE(name);
        KernelOptions inlined, traversed;
        Image a = render(doc, name, InlineGeometry::Rule, &inlined);
        ASSERT_FALSE(inlined.inlineGeometry.slots.empty());
        capacities.push_back(inlineKernelCapacity(inlined.inlineGeometry.slotCount()));
        Image b = render(doc, name, InlineGeometry::Off, &traversed);
        ASSERT_EQ(a.rgb.size(), b.rgb.size());
        int differing = 0;
        for (size_t i = 0; i < a.rgb.size(); ++i)
            differing += std::abs(double(a.rgb[i]) - double(b.rgb[i])) > 1e-4 * (1.0 + std::abs(double(b.rgb[i])));
        EXPECT_EQ(differing, 0);
    }
    EXPECT_EQ(capacities, (std::vector<uint32_t>{16u, 32u, 48u}));
}

// The slots hold every primitive exactly once, with its own type and points, empty slots
// only where a group is padded; each group's box holds its primitives' bounds (else the
// kernel would skip hits); and the room's layout does use what it is for: primitives out
// of leaf order and some group behind its box test.
TEST(InlineGeometry, SlotsHoldEveryPrimitiveOnceInsideItsGroupsBox) {
    for (int extra = -12; extra <= int(INLINE_MAX_PRIMITIVES) - 20; ++extra) {
        if (extra < 0 && extra != -12) continue;
        json doc = mixedRoom("mis", std::max(extra, 0));
        if (extra < 0) doc["shapes"].erase(8);
        const Scene scene = test::sceneFromJson(doc, "inline-slots" + std::to_string(extra));
        const SceneArrays arrays = buildSceneArrays(scene);
        const std::vector<gpu::Primitive>& primitives = arrays.bvh.primitives;
        SCOPED_TRACE(primitives.size());
        const InlineGeometryWords words = inlineGeometryWords(arrays.bvh);
        ASSERT_EQ(words.slots.size() % INLINE_PRIMITIVE_WORDS, 0u);
        const size_t slots = words.slots.size() / INLINE_PRIMITIVE_WORDS;
        ASSERT_GE(slots, primitives.size());
        ASSERT_LE(slots, size_t(INLINE_MAX_PRIMITIVES));
        const size_t groups = (slots + INLINE_GROUP_SIZE - 1) / INLINE_GROUP_SIZE;
        ASSERT_EQ(words.groups.size(), groups * INLINE_GROUP_WORDS);
        std::vector<int> seen(primitives.size(), 0);
        bool reordered = false, someTested = false;
        for (size_t slot = 0; slot < slots; ++slot) {
            const uint32_t* w = &words.slots[slot * INLINE_PRIMITIVE_WORDS];
            const uint32_t* box = &words.groups[(slot / INLINE_GROUP_SIZE) * INLINE_GROUP_WORDS];
            ASSERT_LE(box[6], 1u);
            someTested = someTested || box[6] == 1u;
            if ((w[0] & INLINE_SLOT_TYPE_MASK) == INLINE_SLOT_EMPTY) continue;
            const uint32_t index = w[0] >> INLINE_SLOT_INDEX_SHIFT;
            ASSERT_LT(index, primitives.size());
            ++seen[index];
            reordered = reordered || index != slot;
            const gpu::Primitive& p = primitives[index];
            EXPECT_EQ(w[0] & INLINE_SLOT_TYPE_MASK, p.typeAndNormals & gpu::PRIM_TYPE_MASK);
            const glm::vec3 points[3] = {p.p0, p.p1, p.p2};
            for (int k = 0; k < 9; ++k) EXPECT_EQ(std::bit_cast<float>(w[1 + k]), points[k / 3][k % 3]);
            glm::vec3 lo, hi;
            primitiveBounds(p, lo, hi);
            for (int k = 0; k < 3; ++k) {
                EXPECT_LE(std::bit_cast<float>(box[k]), lo[k]) << "slot " << slot;
                EXPECT_GE(std::bit_cast<float>(box[3 + k]), hi[k]) << "slot " << slot;
            }
        }
        for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "primitive " << i;
        if (extra == 0) {
            EXPECT_TRUE(reordered);
            EXPECT_TRUE(someTested);
        }
    }
}
