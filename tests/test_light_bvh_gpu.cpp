// Light selection "bvh" on the GPU (shaders/lights/light_bvh.glsl) against the host's tree
// (render/light_bvh.h): the GPU's importance and replay give the host's pmf of every item at
// many shading points; the GPU's descents follow the host's pmfs (chi-square), and each
// replayed pmf equals the sampled one exactly. The per-primitive trails the renderer uploads
// (render/light_bvh_arrays.h) lead back to each emitter's own item.
//
// Significance: alpha = 0.01 for the file, Sidak-corrected over kChi2Tests tests; fixed seeds.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "chi2.h"
#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu_fixture.h"
#include "light_bvh_fixtures.h"
#include "render/light_bvh_arrays.h"
#include "render/scene_arrays.h"
#include "tests/light_bvh_test.h"

using namespace penumbra;
using test::mixedLights;
using test::Shading;
using test::shadingPoints;

namespace {

constexpr int kPmfPoints = 24;
constexpr int kSamplePoints = 8;
constexpr int kChi2Tests = kSamplePoints;
constexpr uint32_t kDraws = 1u << 18;

std::vector<VkDescriptorType> bindings() {
    std::vector<VkDescriptorType> types(LIGHT_BVH_TEST_BINDING_COUNT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    types[BINDING_LIGHT_BVH] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    return types;
}

gpu::Kernel& testKernel() {
    static gpu::Kernel kernel(test::gpuContext(), "tests/light_bvh", bindings(), sizeof(gpu::LightBvhTestPush));
    return kernel;
}

// The tree's nodes then items, as BINDING_LIGHT_BVH holds them (render/light_bvh_arrays.h).
struct GpuTree {
    gpu::Buffer texels;
    uint32_t itemsTexel;
};

GpuTree upload(const LightBvh& bvh) {
    std::vector<glm::uvec4> texels(3 * bvh.nodes.size() + bvh.items.size());
    std::memcpy(texels.data(), bvh.nodes.data(), bvh.nodes.size() * sizeof(gpu::LightBvhNode));
    std::memcpy(texels.data() + 3 * bvh.nodes.size(), bvh.items.data(), bvh.items.size() * sizeof(gpu::LightBvhItem));
    return {gpu::Buffer::fromVector(test::gpuContext(), texels, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT),
            uint32_t(3 * bvh.nodes.size())};
}

std::vector<gpu::LightBvhTestRecord> run(const GpuTree& tree, uint32_t mode, const Shading& s, uint32_t count,
                                         uint32_t seed) {
    gpu::LightBvhTestPush push{};
    push.p = s.p;
    push.n = s.n;
    push.mode = mode;
    push.count = count;
    push.seed = seed;
    push.itemsTexel = tree.itemsTexel;
    gpu::Buffer out(test::gpuContext(), VkDeviceSize(count) * sizeof(gpu::LightBvhTestRecord),
                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    gpu::Kernel& kernel = testKernel();
    kernel.bind(BINDING_LIGHT_BVH, tree.texels);
    kernel.bind(LIGHT_BVH_TEST_BINDING_OUT, out);
    kernel.run((count + gpu::LIGHT_BVH_TEST_WORKGROUP_SIZE - 1) / gpu::LIGHT_BVH_TEST_WORKGROUP_SIZE, 1, 1, &push);
    auto records = out.read<gpu::LightBvhTestRecord>();
    records.resize(count);
    return records;
}

}  // namespace

static_assert(sizeof(gpu::LightBvhTestPush) == 48 && sizeof(gpu::LightBvhTestRecord) == 16);

// The same float formulas on both sides: each item's pmf agrees with the host's to float
// rounding. The GPU may fuse a multiply and an add where the host rounds twice, and the
// cone terms (sqrt(1 - cos^2), cos a cos b + sin a sin b) lose relative precision where they
// are small, so an item's relative difference is bounded loosely (kItemRelative) and the
// total variation distance between the two pmfs, which is what sampling sees, tightly
// (kTotalVariation). Both measured figures are printed. The GPU's pmfs sum to 1.
TEST(LightBvhGpu, PmfsOfEveryItemMatchTheHost) {
    constexpr double kItemRelative = 1e-3, kTotalVariation = 1e-6;
    const LightBvh bvh = buildLightBvh(mixedLights(300, 11), 0);
    const GpuTree tree = upload(bvh);
    double worstRelative = 0.0, worstVariation = 0.0;
    for (const Shading& s : shadingPoints(kPmfPoints, 12)) {
        auto records = run(tree, gpu::LIGHT_BVH_TEST_MODE_PMF, s, uint32_t(bvh.items.size()), 0);
        double sum = 0.0, variation = 0.0;
        for (uint32_t i = 0; i < bvh.items.size(); ++i) {
            const double host = lightBvhPmf(bvh, s.p, s.n, i), gpu = records[i].pmf;
            sum += gpu;
            variation += 0.5 * std::abs(gpu - host);
            const double relative = host > 0.0 ? std::abs(gpu - host) / host : (gpu == 0.0 ? 0.0 : 1.0);
            worstRelative = std::max(worstRelative, relative);
            EXPECT_LE(relative, kItemRelative) << "item " << i << ": GPU " << gpu << ", host " << host << " at ("
                                               << s.p.x << ", " << s.p.y << ", " << s.p.z << ")";
        }
        worstVariation = std::max(worstVariation, variation);
        EXPECT_LE(variation, kTotalVariation);
        EXPECT_NEAR(sum, 1.0, 1e-5);
    }
    std::printf("GPU vs host pmfs: largest relative difference %.3g, largest total variation %.3g\n", worstRelative,
                worstVariation);
}

// Descents on the GPU against the host's pmfs: a wrong GPU importance or descent fails the
// chi-square; the replay of the item reached gives its sampled pmf bit for bit.
TEST(LightBvhGpu, DescentsFollowTheHostPmfsAndReplayEqualsSample) {
    const LightBvh bvh = buildLightBvh(mixedLights(200, 13), 0);
    const GpuTree tree = upload(bvh);
    uint32_t seed = 100;
    for (const Shading& s : shadingPoints(kSamplePoints, 14)) {
        auto records = run(tree, gpu::LIGHT_BVH_TEST_MODE_SAMPLE, s, kDraws, seed++);
        std::vector<double> counts(bvh.items.size(), 0.0), pmf(bvh.items.size());
        double sum = 0.0;
        for (uint32_t i = 0; i < bvh.items.size(); ++i) sum += pmf[i] = lightBvhPmf(bvh, s.p, s.n, i);
        ASSERT_NEAR(sum, 1.0, 1e-5);
        for (double& q : pmf) q /= sum;  // the harness wants 1 to 2e-10: float rounding only
        size_t mismatched = 0;
        for (const gpu::LightBvhTestRecord& r : records) {
            ASSERT_LT(r.item, bvh.items.size());
            counts[r.item] += 1.0;
            if (r.replayed != r.pmf) ++mismatched;
        }
        EXPECT_EQ(mismatched, 0u) << "replayed pmfs differ from the sampled ones";
        test::DiscreteChi2Options options;
        options.numTests = kChi2Tests;
        const test::Chi2Result r = test::chi2TestDiscrete(counts, pmf, 0, options);
        EXPECT_TRUE(r.passed) << r.message;
    }
}

// A scene with every kind of light: the tree holds the lights with a position (a mesh
// light's triangles one by one), the table beside it the directional and environment lights
// and the tree, and the trail stored for each emitting primitive is its own item's.
TEST(LightBvhGpu, SceneArraysHoldTheTreeTheTableAndEachEmittersTrail) {
    Scene scene;
    scene.materials.push_back(Material{});
    scene.integrator.lightSelection = LightSelection::Bvh;
    Light point;
    point.type = LightType::Point;
    point.position = {0.0f, 2.0f, 0.0f};
    point.intensity = glm::vec3(3.0f);
    Light spot = point;
    spot.type = LightType::Spot;
    spot.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    spot.cosInner = 0.9f;
    spot.cosOuter = 0.8f;
    Light directional;
    directional.type = LightType::Directional;
    directional.direction = {0.0f, -1.0f, 0.0f};
    directional.intensity = glm::vec3(1.0f);
    Light environment;
    environment.type = LightType::Environment;
    environment.intensity = glm::vec3(0.1f);
    scene.lights = {point, spot, directional, environment};
    Shape sphere;
    sphere.type = ShapeType::Sphere;
    sphere.center = {1.0f, 1.0f, 0.0f};
    sphere.radius = 0.25f;
    sphere.emission = glm::vec3(2.0f);
    Shape quad;
    quad.type = ShapeType::Quad;
    quad.origin = {-1.0f, 2.0f, -1.0f};
    quad.edgeU = {0.5f, 0.0f, 0.0f};
    quad.edgeV = {0.0f, 0.0f, 0.5f};
    quad.emission = glm::vec3(4.0f);
    Shape mesh;
    mesh.type = ShapeType::Mesh;
    mesh.positions = {{0, 3, 0}, {1, 3, 0}, {0, 3, 1}, {1, 3, 1}, {2, 3, 1}};
    mesh.indices = {0, 2, 1, 1, 2, 3, 1, 3, 4};
    mesh.emission = glm::vec3(1.5f);
    Shape floor;
    floor.type = ShapeType::Quad;
    floor.origin = {-5.0f, 0.0f, -5.0f};
    floor.edgeU = {0.0f, 0.0f, 10.0f};
    floor.edgeV = {10.0f, 0.0f, 0.0f};
    scene.shapes = {sphere, quad, mesh, floor};

    const SceneArrays a = buildSceneArrays(scene);
    const LightBvhArrays& t = a.lightBvh;
    ASSERT_EQ(t.tree.items.size(), 2u + 1u + 1u + 3u);  // point, spot, sphere, quad, 3 triangles
    ASSERT_EQ(t.tableCount, 3u);                        // directional, environment, the tree
    std::vector<uint32_t> tableItems;
    for (uint32_t k = 0; k < t.tableCount; ++k) {
        EXPECT_FLOAT_EQ(a.lightTable[t.tableOffset + k].pmf, 1.0f / 3.0f);
        tableItems.push_back(a.lightTable[t.tableOffset + k].item);
    }
    std::sort(tableItems.begin(), tableItems.end());
    EXPECT_EQ(tableItems.back(), gpu::NO_LIGHT);
    EXPECT_EQ(a.lights[tableItems[0]].type, gpu::LIGHT_DIRECTIONAL);
    EXPECT_EQ(a.lights[tableItems[1]].type, gpu::LIGHT_ENVIRONMENT);
    // The spot light's axis survives its octahedral encoding.
    for (const LightBounds& b : lightBoundsOf(a))
        if (a.lights[b.light].type == gpu::LIGHT_SPOT) EXPECT_NEAR(glm::dot(b.axis, spot.direction), 1.0f, 1e-5f);
    for (const gpu::LightBvhItem& item : t.tree.items) {
        const gpu::Light& light = a.lights[item.light];
        uint32_t prim = item.primitive != ~0u ? item.primitive : light.first;
        if (light.type == gpu::LIGHT_POINT || light.type == gpu::LIGHT_SPOT) continue;
        EXPECT_EQ(a.bvh.primitives[prim].light, item.light);
        const glm::uvec4 texel = t.texels[t.trailsTexel + prim / 2];
        const glm::uvec2 trail = prim % 2 == 0 ? glm::uvec2(texel.x, texel.y) : glm::uvec2(texel.z, texel.w);
        EXPECT_EQ(trail, glm::uvec2(item.trailLow, item.trailHigh)) << "primitive " << prim;
    }
    // Other selections build none of it.
    scene.integrator.lightSelection = LightSelection::Power;
    EXPECT_TRUE(buildSceneArrays(scene).lightBvh.texels.empty());
}
