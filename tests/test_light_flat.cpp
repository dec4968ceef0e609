// The flat form of a small light tree (render/light_flat.h, shaders/lights/light_flat.glsl):
// on the host, the pmfs over all leaves sum to 1, a draw's pmf is the one replayed for its
// leaf, draws follow the claimed pmf (chi-square) and a deliberately wrong claim fails;
// where every importance is zero the leaves are weighed by power. On the GPU, with the
// leaves as specialization constants as the render kernels get them, the pmfs of every
// leaf match the host's, draws follow the host's pmfs and each replayed pmf (found again
// through the leaf's hit primitive, as MIS does) equals the sampled one bit for bit. The
// render kernels use it exactly for trees of at most LIGHT_FLAT_MAX_LEAVES leaves with
// inline geometry, and renders with it match closed forms, MIS included.
//
// Significance: alpha = 0.01 per chi-square family, Sidak-corrected over its tests; fixed seeds.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "chi2.h"
#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu_fixture.h"
#include "light_bvh_fixtures.h"
#include "many_light_scenes.h"
#include "render/kernel_options.h"
#include "render/light_bvh_arrays.h"
#include "render/light_flat.h"
#include "render/scene_arrays.h"
#include "render_helpers.h"
#include "tests/light_bvh_test.h"

using namespace penumbra;
using test::mixedLights;
using test::Shading;
using test::shadingPoints;

namespace {

// Trees of 1 to LIGHT_FLAT_MAX_LEAVES mixed lights; leaf i's hit primitive 100 + i for
// every other leaf, NO_HIT for the rest (point and spot lights have none).
struct Flat {
    LightBvh bvh;
    std::vector<gpu::LightFlatLeaf> leaves;
};
Flat smallTree(uint32_t count, uint32_t seed) {
    Flat f{buildLightBvh(mixedLights(count, seed), 0), {}};
    std::vector<uint32_t> hit(f.bvh.items.size());
    for (uint32_t i = 0; i < hit.size(); ++i) hit[i] = i % 2 == 0 ? 100u + i : gpu::NO_HIT;
    f.leaves = lightFlatLeaves(f.bvh, hit);
    return f;
}

std::vector<double> claimedPmf(const std::vector<gpu::LightFlatLeaf>& leaves, const Shading& s) {
    std::vector<double> pmf(leaves.size());
    double sum = 0.0;
    for (uint32_t i = 0; i < leaves.size(); ++i) sum += pmf[i] = lightFlatPmf(leaves, s.p, s.n, i);
    // Float quotients of one float sum: 1 within rounding; the harness wants 1 to 2e-10.
    for (double& q : pmf) q /= sum;
    return pmf;
}

constexpr int kPoints = 6;
constexpr uint32_t kDraws = 1u << 17;

// ---- GPU: the test kernel with the leaves as specialization constants ----

std::vector<gpu::LightBvhTestRecord> runFlat(const std::vector<gpu::LightFlatLeaf>& leaves, uint32_t mode,
                                             const Shading& s, uint32_t count, uint32_t seed) {
    std::vector<uint32_t> spec(SPEC_COUNT, 0u);
    const std::vector<uint32_t> words = lightFlatWords(leaves);
    spec[SPEC_LIGHT_FLAT_COUNT] = uint32_t(leaves.size());
    std::copy(words.begin(), words.end(), spec.begin() + SPEC_LIGHT_FLAT_FIRST);
    std::vector<VkDescriptorType> types(LIGHT_BVH_TEST_BINDING_COUNT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    gpu::Kernel kernel(test::gpuContext(), "tests/light_flat", types, sizeof(gpu::LightBvhTestPush), spec);
    gpu::LightBvhTestPush push{};
    push.p = s.p;
    push.n = s.n;
    push.mode = mode;
    push.count = count;
    push.seed = seed;
    gpu::Buffer out(test::gpuContext(), VkDeviceSize(count) * sizeof(gpu::LightBvhTestRecord),
                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    kernel.bind(LIGHT_BVH_TEST_BINDING_OUT, out);
    kernel.run((count + gpu::LIGHT_BVH_TEST_WORKGROUP_SIZE - 1) / gpu::LIGHT_BVH_TEST_WORKGROUP_SIZE, 1, 1, &push);
    auto records = out.read<gpu::LightBvhTestRecord>();
    records.resize(count);
    return records;
}

}  // namespace

TEST(LightBvhFlat, PmfsSumToOneAndADrawsPmfIsItsLeafsReplayedPmf) {
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (uint32_t count = 1; count <= LIGHT_FLAT_MAX_LEAVES; ++count) {
        const Flat f = smallTree(count, 30 + count);
        ASSERT_EQ(f.leaves.size(), count);
        for (const Shading& s : shadingPoints(30, 32)) {
            double sum = 0.0;
            for (uint32_t i = 0; i < count; ++i) sum += lightFlatPmf(f.leaves, s.p, s.n, i);
            EXPECT_NEAR(sum, 1.0, 1e-6);  // at most 8 float quotients of one sum
            for (int k = 0; k < 20; ++k) {
                const LightBvhSample d = sampleLightFlat(f.leaves, s.p, s.n, u(rng));
                ASSERT_GE(d.item, 0);
                EXPECT_GT(d.pmf, 0.0f);
                EXPECT_EQ(d.pmf, lightFlatPmf(f.leaves, s.p, s.n, uint32_t(d.item)));  // exactly
            }
        }
    }
}

// Each leaf is weighed by the importance of its own node in the tree.
TEST(LightBvhFlat, LeavesCarryTheirNodesImportanceItemAndHitPrimitive) {
    const Flat f = smallTree(7, 40);
    for (const gpu::LightBvhNode& node : f.bvh.nodes) {
        if (!(node.childOrItem & gpu::LIGHT_BVH_LEAF)) continue;
        const uint32_t item = node.childOrItem & gpu::LIGHT_BVH_INDEX_MASK;
        const gpu::LightFlatLeaf& leaf = f.leaves[item];
        EXPECT_EQ(leaf.light, f.bvh.items[item].light);
        EXPECT_EQ(leaf.primitive, f.bvh.items[item].primitive);
        EXPECT_EQ(leaf.hitPrimitive, item % 2 == 0 ? 100u + item : gpu::NO_HIT);
        for (const Shading& s : shadingPoints(10, 41))
            EXPECT_EQ(lightImportance(leaf.terms, s.p, s.n), lightBvhImportance(node, s.p, s.n));
    }
}

TEST(LightBvhFlat, HostDrawsFollowTheClaimedPmfChiSquare) {
    const Flat f = smallTree(8, 50);
    std::mt19937 rng(51);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (const Shading& s : shadingPoints(kPoints, 52)) {
        const std::vector<double> pmf = claimedPmf(f.leaves, s);
        std::vector<double> counts(pmf.size(), 0.0);
        for (uint32_t k = 0; k < kDraws; ++k) counts[sampleLightFlat(f.leaves, s.p, s.n, u(rng)).item] += 1.0;
        test::DiscreteChi2Options options;
        options.numTests = kPoints;
        const test::Chi2Result r = test::chi2TestDiscrete(counts, pmf, 0, options);
        EXPECT_TRUE(r.passed) << r.message;
    }
}

// A deliberately wrong claim fails the same test: the largest and smallest pmfs swapped.
TEST(LightBvhFlat, ChiSquareRejectsAWrongPmf) {
    const Flat f = smallTree(8, 50);
    const Shading s{{0.5f, 1.0f, -0.5f}, {0.0f, 1.0f, 0.0f}};
    std::vector<double> pmf = claimedPmf(f.leaves, s);
    auto hi = std::max_element(pmf.begin(), pmf.end()), lo = std::min_element(pmf.begin(), pmf.end());
    ASSERT_GT(*hi - *lo, 0.01);
    std::swap(*hi, *lo);
    std::mt19937 rng(53);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<double> counts(pmf.size(), 0.0);
    for (uint32_t k = 0; k < kDraws; ++k) counts[sampleLightFlat(f.leaves, s.p, s.n, u(rng)).item] += 1.0;
    EXPECT_FALSE(test::chi2TestDiscrete(counts, pmf, 0, {}).passed);
}

// Behind every one-sided emitter every importance is zero: the leaves are then weighed by
// their powers, as the descent's childWeights does, so that the pmf still sums to 1.
TEST(LightBvhFlat, WhereEveryImportanceIsZeroTheLeavesAreWeighedByPower) {
    std::vector<LightBounds> lights;
    for (uint32_t i = 0; i < 3; ++i)
        lights.push_back(flatLightBounds({float(i), 2.0f, 0.0f}, {float(i) + 0.5f, 2.0f, 0.5f}, {0.0f, -1.0f, 0.0f},
                                         0.25f, 1.0f + float(i), false, i, ~0u));
    const LightBvh bvh = buildLightBvh(lights, 0);
    const std::vector<gpu::LightFlatLeaf> leaves = lightFlatLeaves(bvh, std::vector<uint32_t>(3, gpu::NO_HIT));
    const glm::vec3 above(0.5f, 5.0f, 0.2f), n(0.0f, 1.0f, 0.0f);
    float total = 0.0f, powers = 0.0f;
    for (const gpu::LightFlatLeaf& leaf : leaves) {
        ASSERT_EQ(lightImportance(leaf.terms, above, n), 0.0f);
        powers += leaf.terms.power;
    }
    lightFlatWeights(leaves, above, n, total);
    EXPECT_EQ(total, powers);
    for (uint32_t i = 0; i < leaves.size(); ++i)
        EXPECT_FLOAT_EQ(lightFlatPmf(leaves, above, n, i), leaves[i].terms.power / powers);
}

// The GPU's pmf of every leaf is the host's to float rounding, and sums to 1. As in
// LightBvhGpu's PmfsOfEveryItemMatchTheHost, the GPU may fuse what the host rounds twice and
// the cone terms lose relative precision where they are small: a leaf's relative
// difference is bounded loosely (kLeafRelative). Here a pmf is one quotient of the leaf's
// importance, not a product of ratios that mostly cancel, so the total variation is about
// the relative difference of the larger pmfs: bounded at 1e-5 (about 80 float epsilons).
TEST(LightBvhFlatGpu, PmfsOfEveryLeafMatchTheHost) {
    constexpr double kLeafRelative = 1e-3, kTotalVariation = 1e-5;
    double worstRelative = 0.0, worstVariation = 0.0;
    for (uint32_t count = 1; count <= LIGHT_FLAT_MAX_LEAVES; ++count) {
        const Flat f = smallTree(count, 60 + count);
        for (const Shading& s : shadingPoints(12, 61)) {
            auto records = runFlat(f.leaves, gpu::LIGHT_BVH_TEST_MODE_PMF, s, count, 0);
            double sum = 0.0, variation = 0.0;
            for (uint32_t i = 0; i < count; ++i) {
                const double host = lightFlatPmf(f.leaves, s.p, s.n, i), gpu = records[i].pmf;
                sum += gpu;
                variation += 0.5 * std::abs(gpu - host);
                const double relative = host > 0.0 ? std::abs(gpu - host) / host : (gpu == 0.0 ? 0.0 : 1.0);
                worstRelative = std::max(worstRelative, relative);
                EXPECT_LE(relative, kLeafRelative)
                    << count << " leaves, leaf " << i << ": GPU " << gpu << ", host " << host;
            }
            worstVariation = std::max(worstVariation, variation);
            EXPECT_LE(variation, kTotalVariation);
            EXPECT_NEAR(sum, 1.0, 1e-6);
        }
    }
    std::printf("flat form, GPU vs host pmfs: largest relative difference %.3g, largest total variation %.3g\n",
                worstRelative, worstVariation);
}

// Draws on the GPU against the host's pmfs (chi-square); each draw's pmf replayed through
// its leaf's hit primitive (where it has one) equals the sampled one exactly, and the draw
// names its leaf's light and item primitive.
TEST(LightBvhFlatGpu, DrawsFollowTheHostPmfsAndReplayEqualsSample) {
    const Flat f = smallTree(8, 70);
    uint32_t seed = 200;
    for (const Shading& s : shadingPoints(kPoints, 71)) {
        auto records = runFlat(f.leaves, gpu::LIGHT_BVH_TEST_MODE_SAMPLE, s, kDraws, seed++);
        const std::vector<double> pmf = claimedPmf(f.leaves, s);
        std::vector<double> counts(pmf.size(), 0.0);
        size_t mismatched = 0, misnamed = 0;
        for (const gpu::LightBvhTestRecord& r : records) {
            ASSERT_LT(r.item, pmf.size());
            counts[r.item] += 1.0;
            if (r.replayed != r.pmf || !(r.pmf > 0.0f)) ++mismatched;
            const gpu::LightFlatLeaf& leaf = f.leaves[r.item];
            if (std::bit_cast<uint32_t>(r.pad) != ((leaf.light << 16) | (leaf.primitive & 0xffffu))) ++misnamed;
        }
        EXPECT_EQ(mismatched, 0u) << "replayed pmfs differ from the sampled ones";
        EXPECT_EQ(misnamed, 0u) << "draws name another leaf's light or primitive";
        test::DiscreteChi2Options options;
        options.numTests = kPoints;
        const test::Chi2Result r = test::chi2TestDiscrete(counts, pmf, 0, options);
        EXPECT_TRUE(r.passed) << r.message;
    }
}

// ---- The render kernels ----

namespace {

constexpr double kAlbedo = 0.6;
constexpr double kAlpha = 1e-3;
constexpr double kHalf = 3.0;

nlohmann::json direct(const std::string& strategy, const std::string& selection) {
    return {{"type", "direct"}, {"strategy", strategy}, {"light_selection", selection}};
}

// Four point lights and a downward-facing emitting quad (radiance Le, height h) over the
// diffuse plane: five leaves, two primitives, inline. Returns the quad's outline.
std::vector<glm::dvec3> addQuadLight(nlohmann::json& doc, double Le, double h) {
    doc["shapes"].push_back({{"type", "quad"},
                             {"origin", {-2.0, h, 3.5}},
                             {"edge_u", {4.0, 0.0, 0.0}},
                             {"edge_v", {0.0, 0.0, 4.0}},
                             {"emission", {Le, Le, Le}},
                             {"material", "black"}});
    return {{-2, h, 3.5}, {2, h, 3.5}, {2, h, 7.5}, {-2, h, 7.5}};
}

// The kernel's SPEC_LIGHT_FLAT_COUNT (or, with `alone`, SPEC_LIGHT_FLAT_ALONE) for doc.
uint32_t flatLeavesOf(const nlohmann::json& doc, const std::string& selection, InlineGeometry inlined,
                      bool alone = false) {
    nlohmann::json d = doc;
    d["integrator"] = direct("mis", selection);
    const Scene scene = test::sceneFromJson(d, "light-flat-options");
    const KernelOptions o = makeKernelOptions(scene, buildSceneArrays(scene), EmitterFirst::Rule, inlined);
    return o.specialization()[alone ? SPEC_LIGHT_FLAT_ALONE : SPEC_LIGHT_FLAT_COUNT];
}

// A directional light of irradiance E travelling along (1, -2, 1): the quad's shadow falls
// outside the camera's view. Returns its radiance off the plane.
double addDirectionalLight(nlohmann::json& doc, double E) {
    doc["lights"].push_back({{"type", "directional"}, {"direction", {1, -2, 1}}, {"irradiance", {E, E, E}}});
    return kAlbedo / M_PI * E * 2.0 / std::sqrt(6.0);
}

}  // namespace

// The rule: light selection "bvh", inline geometry, 1 to LIGHT_FLAT_MAX_LEAVES items.
TEST(LightBvhFlat, OnlySmallTreesInInlineKernelsUseTheFlatForm) {
    nlohmann::json doc = test::diffusePlaneScene(1, 1, 0.0, kHalf, kAlbedo);
    test::addPointLights(doc, test::randomPointLights(4, 80));
    addQuadLight(doc, 3.0, 2.2);
    EXPECT_EQ(flatLeavesOf(doc, "bvh", InlineGeometry::Rule), 5u);
    EXPECT_EQ(flatLeavesOf(doc, "bvh", InlineGeometry::Rule, true), 1u);  // no light at infinity
    EXPECT_EQ(flatLeavesOf(doc, "bvh", InlineGeometry::Off), 0u);
    EXPECT_EQ(flatLeavesOf(doc, "bvh", InlineGeometry::Off, true), 0u);
    EXPECT_EQ(flatLeavesOf(doc, "power", InlineGeometry::Rule), 0u);
    nlohmann::json sun = doc;
    addDirectionalLight(sun, 1.0);
    EXPECT_EQ(flatLeavesOf(sun, "bvh", InlineGeometry::Rule), 5u);
    EXPECT_EQ(flatLeavesOf(sun, "bvh", InlineGeometry::Rule, true), 0u);
    nlohmann::json eight = test::diffusePlaneScene(1, 1, 0.0, kHalf, kAlbedo);
    test::addEmittingSquareMesh(eight, 3.0, 2.2);  // eight triangles: eight leaves
    EXPECT_EQ(flatLeavesOf(eight, "bvh", InlineGeometry::Rule), 8u);
    test::addPointLights(eight, test::randomPointLights(1, 81));
    EXPECT_EQ(flatLeavesOf(eight, "bvh", InlineGeometry::Rule), 0u);
}

// Renders through the flat form against the closed form: point lights and a quad light
// (a whole light, found again by its primitive), the same with a directional light beside
// the tree (the table drawn first), and a mesh light's eight triangles (each its own leaf),
// under light sampling and MIS, where a wrong replayed pmf biases the image.
TEST(LightBvhFlatRender, FewLightsMatchTheClosedFormWithMis) {
    const std::vector<test::PointLight> points = test::randomPointLights(4, 82);
    const double Le = 3.0, h = 2.2;
    nlohmann::json doc = test::diffusePlaneScene(128, 6, 0.0, kHalf, kAlbedo);
    test::addPointLights(doc, points);
    const std::vector<glm::dvec3> outline = addQuadLight(doc, Le, h);
    ASSERT_EQ(flatLeavesOf(doc, "bvh", InlineGeometry::Rule), 5u);
    test::expectTopDownMatches(
        doc, {direct("mis", "bvh"), direct("light", "bvh")},
        [&](glm::dvec3 x) {
            return kAlbedo / M_PI * (test::pointLightsIrradiance(points, x) + test::polygonIrradiance(outline, x, Le));
        },
        "flat-quad", kAlpha);

    nlohmann::json sun = doc;
    const double sunRadiance = addDirectionalLight(sun, 1.0);
    ASSERT_EQ(flatLeavesOf(sun, "bvh", InlineGeometry::Rule, true), 0u);
    test::expectTopDownMatches(
        sun, {direct("mis", "bvh")},
        [&](glm::dvec3 x) {
            return sunRadiance +
                   kAlbedo / M_PI * (test::pointLightsIrradiance(points, x) + test::polygonIrradiance(outline, x, Le));
        },
        "flat-quad-sun", kAlpha);

    nlohmann::json mesh = test::diffusePlaneScene(128, 7, 0.0, kHalf, kAlbedo);
    const std::vector<glm::dvec3> square = test::addEmittingSquareMesh(mesh, Le, h);
    ASSERT_EQ(flatLeavesOf(mesh, "bvh", InlineGeometry::Rule), 8u);
    test::expectTopDownMatches(
        mesh, {direct("mis", "bvh"), direct("light", "bvh")},
        [&](glm::dvec3 x) { return kAlbedo / M_PI * test::polygonIrradiance(square, x, Le); }, "flat-mesh", kAlpha);
}
