// The BVH and ray-primitive intersection: the CPU tree agrees with brute force, the GLSL
// traversal on lavapipe agrees with the CPU, degenerate inputs build and traverse, large
// builds stay within the GPU stack bound, and secondary rays started with offsetRayOrigin
// never re-hit their own primitive. All scenes and rays come from fixed seeds.
#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "bvh/bvh.h"
#include "bvh/intersect.h"
#include "gpu/kernel.h"
#include "gpu_fixture.h"
#include "render/inline_geometry.h"
#include "render/kernel_options.h"
#include "render/node_reads.h"

using namespace penumbra;
using glm::vec3;

namespace {

constexpr float kInf = 3.402823466e38f;  // FLOAT_MAX of common/math.glsl: "no limit"

struct Random {
    std::mt19937 engine;
    explicit Random(uint32_t seed) : engine(seed) {}
    float uniform(float lo = 0.0f, float hi = 1.0f) { return std::uniform_real_distribution<float>(lo, hi)(engine); }
    vec3 inBox(float lo, float hi) { return vec3(uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)); }
    vec3 unitVector() {
        float z = uniform(-1.0f, 1.0f), phi = uniform(0.0f, 6.2831853f), r = std::sqrt(std::max(0.0f, 1 - z * z));
        return vec3(r * std::cos(phi), r * std::sin(phi), z);
    }
};

gpu::Primitive triangle(vec3 a, vec3 b, vec3 c) { return {a, gpu::PRIM_TRIANGLE, b, 0u, c, gpu::NO_LIGHT}; }
gpu::Primitive sphere(vec3 centre, float radius) {
    return {centre, gpu::PRIM_SPHERE, vec3(radius, 0, 0), 0u, vec3(0), gpu::NO_LIGHT};
}
gpu::Primitive quad(vec3 corner, vec3 u, vec3 v) { return {corner, gpu::PRIM_QUAD, u, 0u, v, gpu::NO_LIGHT}; }

// Random triangles, spheres and quads scattered in [-extent, extent]^3.
std::vector<gpu::Primitive> randomScene(Random& rng, uint32_t triangles, uint32_t spheres, uint32_t quads,
                                        float extent = 10.0f) {
    std::vector<gpu::Primitive> scene;
    for (uint32_t i = 0; i < triangles; ++i) {
        vec3 c = rng.inBox(-extent, extent);
        float size = rng.uniform(0.1f, 1.5f);
        scene.push_back(triangle(c + size * rng.inBox(-1, 1), c + size * rng.inBox(-1, 1), c + size * rng.inBox(-1, 1)));
    }
    for (uint32_t i = 0; i < spheres; ++i) scene.push_back(sphere(rng.inBox(-extent, extent), rng.uniform(0.05f, 0.8f)));
    for (uint32_t i = 0; i < quads; ++i)
        scene.push_back(quad(rng.inBox(-extent, extent), rng.uniform(0.2f, 2.0f) * rng.unitVector(),
                             rng.uniform(0.2f, 2.0f) * rng.unitVector()));
    std::shuffle(scene.begin(), scene.end(), rng.engine);
    return scene;
}

// ---- The GPU side: tests/bvh_trace.comp -------------------------------------------------

struct TraceRay {
    glm::vec4 originTMax;
    glm::vec4 dir;
};
struct TraceResult {
    float t;
    uint32_t primitive;
    uint32_t anyHit;
    uint32_t pad;
};
static_assert(sizeof(TraceRay) == 32 && sizeof(TraceResult) == 16);

// The test kernels' descriptor set: their own buffers at 0 and 1, the scene's at the render
// kernels' BINDING_* numbers (types as in render/renderer.cpp); unused ones stay unbound.
std::vector<VkDescriptorType> sceneBindings() {
    std::vector<VkDescriptorType> types(BINDING_COUNT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    types[BINDING_NODES] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_PRIMITIVE_TEXELS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    return types;
}

// A BVH's nodes and primitives (and shading normals) uploaded the way the renderer does.
struct SceneBuffers {
    gpu::Buffer nodes, primitives, normals;
    SceneBuffers(const gpu::Context& ctx, const Bvh& bvh, const std::vector<gpu::TriangleNormals>& shadingNormals)
        : nodes(gpu::Buffer::fromVector(ctx, bvh.wideNodes,
                                        VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                            gpu::deviceAddressUsage(ctx))),
          primitives(gpu::Buffer::fromVector(
              ctx, bvh.primitives, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT)),
          normals(gpu::Buffer::fromVector(ctx, shadingNormals)) {}
    void bind(gpu::Kernel& kernel) const {
        kernel.bind(BINDING_NODES, nodes);
        kernel.bind(BINDING_NODE_WORDS, nodes);
        kernel.bind(BINDING_PRIMITIVES, primitives);
        kernel.bind(BINDING_PRIMITIVE_TEXELS, primitives);
        kernel.bind(BINDING_NORMALS, normals);
    }
};

// A traversal stack entry no push writes: a child reference never has every bit set
// (offset + primCount <= BVH_MAX_PRIMITIVES).
constexpr uint32_t kUnwrittenEntry = 0xffffffffu;

// Runs the test kernel `name` over the scene's buffers: one invocation per input (binding
// 0, 64 per workgroup), each writing one Result (binding 1). The push constants are the
// input count, the node buffer's device address, the traversal stacks' address and
// entries per stack (bvh_trace.comp's "_address" variant: BVH_STACKS_PER_INVOCATION stacks
// of childStackDepth entries, as the renderer gives them, unless `stackDepth` says
// otherwise; most of these scenes' rays seldom fill the stack, so
// Bvh.StackDepthIsTheLongestPathsInteriorNodes checks the count itself, with rays that do),
// the primitives beside the tree, and `pairs` (bvh_trace.comp: trace through tracePair).
// With `stackEntries`, the stacks start as kUnwrittenEntry and are read back into it after
// the run, BVH_STACKS_PER_INVOCATION * `depth` entries per invocation.
template <class Result, class Input>
std::vector<Result> runSceneKernel(const char* name, const Bvh& bvh,
                                   const std::vector<gpu::TriangleNormals>& shadingNormals,
                                   const std::vector<Input>& inputs, const std::vector<uint32_t>& specialization = {},
                                   uint32_t stackDepth = 0, std::vector<uint32_t>* stackEntries = nullptr,
                                   bool pairs = false) {
    auto& ctx = test::gpuContext();
    auto inputBuffer = gpu::Buffer::fromVector(ctx, inputs);
    gpu::Buffer results(ctx, inputs.size() * sizeof(Result), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    SceneBuffers scene(ctx, bvh, shadingNormals);
    const uint32_t groups = uint32_t((inputs.size() + 63) / 64),
                   depth = stackDepth > 0 ? stackDepth : childStackDepth(bvh.wideNodes);
    gpu::Buffer stacks = gpu::Buffer::fromVector(
        ctx, std::vector<uint32_t>(size_t(groups) * 64 * gpu::BVH_STACKS_PER_INVOCATION * depth, kUnwrittenEntry),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | gpu::deviceAddressUsage(ctx));
    const uint32_t push[9] = {uint32_t(inputs.size()),
                              uint32_t(scene.nodes.address()),
                              uint32_t(scene.nodes.address() >> 32),
                              uint32_t(stacks.address()),
                              uint32_t(stacks.address() >> 32),
                              depth,
                              bvh.besideFirst(),
                              bvh.besideCount,
                              pairs ? 1u : 0u};
    gpu::Kernel kernel(ctx, name, sceneBindings(), sizeof(push), specialization);
    kernel.bind(0, inputBuffer);
    kernel.bind(1, results);
    scene.bind(kernel);
    kernel.run(groups, 1, 1, push);
    if (stackEntries) *stackEntries = stacks.read<uint32_t>();
    auto out = results.read<Result>();
    out.resize(inputs.size());
    return out;
}

// tests/bvh_trace, or its "_inline<N>" variant where `specialization` puts primitives inline,
// or its "_int64" one where it reads nodes 32 bytes at a time, "_address" through the node
// buffer's device address (render/node_reads.h); with `pairs` ("_address" only), the
// closest and any hits are traced two rays at a time (geometry/bvh.glsl, tracePair).
std::vector<TraceResult> traceOnGpu(const Bvh& bvh, const std::vector<TraceRay>& rays,
                                    const std::vector<uint32_t>& specialization = {}, bool pairs = false) {
    const uint32_t inlined = specialization.size() > SPEC_INLINE_COUNT ? specialization[SPEC_INLINE_COUNT] : 0;
    const uint32_t nodeReads = specialization.size() > SPEC_NODE_READS ? specialization[SPEC_NODE_READS] : 0;
    const std::string name = inlined > 0 ? "tests/bvh_trace_inline" + std::to_string(inlineKernelCapacity(inlined))
                                         : nodeReadsKernel("tests/bvh_trace", nodeReads);
    return runSceneKernel<TraceResult>(name.c_str(), bvh, {}, rays, specialization, 0, nullptr, pairs);
}

// The traversal kernels' specialization with nodes read as `nodeReads` (NODE_READS_*); the
// default ({}) reads them as texels (render/node_reads.h).
std::vector<uint32_t> nodeReadsSpecialization(uint32_t nodeReads) {
    KernelOptions options;
    options.nodeReads = nodeReads;
    return options.specialization();
}

// Whether the test device runs the "_address" kernels: it has shaderInt64 and
// bufferDeviceAddress (lavapipe has both).
bool deviceReadsNodesThroughAddresses() {
    return test::gpuContext().info().shaderInt64 && test::gpuContext().info().bufferDeviceAddress;
}

// Every way a kernel reads nodes on the test device: texels, the storage buffer in loads of
// 16 bytes, and of 32 where the device has shaderInt64 (lavapipe has), and those through the
// buffer's device address where it also has bufferDeviceAddress (lavapipe has), and, for
// those, the rays traced two at a time as the render kernel traces them (tracePair).
struct NodeReadsVariant {
    std::vector<uint32_t> specialization;
    std::string label;
    bool pairs = false;
};
std::vector<NodeReadsVariant> everyNodeReads() {
    std::vector<NodeReadsVariant> reads = {{{}, "texels"}, {nodeReadsSpecialization(NODE_READS_STORAGE), "storage"}};
    if (test::gpuContext().info().shaderInt64)
        reads.push_back({nodeReadsSpecialization(NODE_READS_STORAGE_32), "storage32"});
    if (deviceReadsNodesThroughAddresses()) {
        reads.push_back({nodeReadsSpecialization(NODE_READS_ADDRESS), "address"});
        reads.push_back({nodeReadsSpecialization(NODE_READS_ADDRESS), "address_pairs", true});
    }
    return reads;
}

// The most traversal stack entries that any of `rays` used in the "_address" trace kernel,
// whose stacks hold child references (its closest-hit and any-hit queries share a ray's
// entries). It runs with `depth` entries per ray, more than it should need, so that the
// kernel's clamp to the last entry hides no overflow; a push leaves its entry written, and
// pops do not clear it.
uint32_t gpuStackHighWater(const Bvh& bvh, const std::vector<TraceRay>& rays, uint32_t depth) {
    std::vector<uint32_t> entries;
    runSceneKernel<TraceResult>(nodeReadsKernel("tests/bvh_trace", NODE_READS_ADDRESS).c_str(), bvh, {}, rays,
                                nodeReadsSpecialization(NODE_READS_ADDRESS), depth, &entries);
    uint32_t deepest = 0;
    for (size_t ray = 0; ray < rays.size(); ++ray)
        for (uint32_t used = depth; used > deepest; --used)
            if (entries[(ray * gpu::BVH_STACKS_PER_INVOCATION) * depth + used - 1] != kUnwrittenEntry) {
                deepest = used;
                break;
            }
    return deepest;
}

// Origins uniform in [-originExtent, originExtent]^3, directions uniform on the sphere; with
// `aimAt`, half of the rays instead head for the bounds centre of a random primitive (with a
// little jitter), so that small scenes are hit often too.
std::vector<TraceRay> randomRays(Random& rng, uint32_t count, float originExtent,
                                 const std::vector<gpu::Primitive>* aimAt = nullptr) {
    std::vector<TraceRay> rays(count);
    for (auto& ray : rays) {
        vec3 origin = rng.inBox(-originExtent, originExtent);
        vec3 dir = rng.unitVector();
        if (aimAt && !aimAt->empty() && rng.uniform() < 0.5f) {
            vec3 lo, hi;
            primitiveBounds((*aimAt)[std::min(size_t(rng.uniform() * aimAt->size()), aimAt->size() - 1)], lo, hi);
            vec3 target = 0.5f * (lo + hi) + 0.1f * (hi - lo) * rng.inBox(-1, 1);
            if (glm::length(target - origin) > 0.0f) dir = glm::normalize(target - origin);
        }
        ray = {glm::vec4(origin, kInf), glm::vec4(dir, 0)};
    }
    return rays;
}

std::string describe(const TraceRay& ray) {
    std::ostringstream s;
    s.precision(9);
    s << "o=(" << ray.originTMax.x << "," << ray.originTMax.y << "," << ray.originTMax.z << ") d=(" << ray.dir.x << ","
      << ray.dir.y << "," << ray.dir.z << ") tMax=" << ray.originTMax.w;
    return s.str();
}

// CPU BVH (with either kind of stack entry) against CPU brute force on the same math: t must
// be bitwise equal, the primitive equal unless two primitives are hit at exactly the same t
// (then either is right).
struct CpuComparison {
    uint32_t hits = 0, ties = 0, failures = 0;
    std::string firstFailure;
};

CpuComparison compareCpu(const std::vector<gpu::Primitive>& scene, const Bvh& bvh, const std::vector<TraceRay>& rays) {
    CpuComparison result;
    for (const TraceRay& ray : rays) {
        vec3 o(ray.originTMax), d(ray.dir);
        float tMax = ray.originTMax.w;
        auto reference = intersectBruteForce(scene, o, d, tMax);
        auto hit = intersectClosest(bvh, o, d, tMax);
        bool any = intersectAny(bvh, o, d, tMax);
        // The traversal with node entries on its stack finds the same distance.
        auto nodesHit = intersectClosest(bvh, o, d, tMax, nullptr, StackEntries::Nodes);
        bool nodesAny = intersectAny(bvh, o, d, tMax, nullptr, StackEntries::Nodes);
        bool ok = bool(reference) == bool(hit) && any == bool(reference) && bool(nodesHit) == bool(hit) &&
                  nodesAny == any && (!hit || nodesHit->t == hit->t);
        if (ok && reference) {
            ++result.hits;
            ok = hit->t == reference->t;
            if (ok && bvh.originalIndex[hit->primitive] != reference->primitive) ++result.ties;
        }
        if (!ok && result.failures++ == 0) result.firstFailure = describe(ray);
    }
    return result;
}

// tMax of `rays`: half unlimited, a quarter random in [0.5, longest), a quarter half-way to
// the closest hit (so any-hit must report nothing while a hit lies further along).
void mixRayLengths(Random& rng, const Bvh& bvh, std::vector<TraceRay>& rays, float longest) {
    for (size_t i = 0; i < rays.size(); ++i) {
        if (i % 4 == 2) rays[i].originTMax.w = rng.uniform(0.5f, longest);
        if (i % 4 == 3) {
            auto hit = intersectClosest(bvh, vec3(rays[i].originTMax), vec3(rays[i].dir), kInf);
            if (hit) rays[i].originTMax.w = 0.5f * hit->t;
        }
    }
}

// The GPU's closest and any hits of `rays` (tests/bvh_trace.comp with `specialization`)
// against CPU brute force over `scene`; `label` names the summary line and the log file.
void expectGpuMatchesCpuBruteForce(const std::vector<gpu::Primitive>& scene, const Bvh& bvh,
                                   const std::vector<TraceRay>& rays, const std::vector<uint32_t>& specialization,
                                   const std::string& label, bool pairs = false) {
    const uint32_t rayCount = uint32_t(rays.size());
    auto gpuStart = std::chrono::steady_clock::now();
    auto gpuResults = traceOnGpu(bvh, rays, specialization, pairs);
    double gpuSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - gpuStart).count();

    // Tolerance on t: GPU and CPU round differently (and lavapipe may fuse multiply-adds);
    // 1e-4 relative is ~1000 ulps, far below any distance between distinct surfaces here.
    auto close = [](float a, float b) { return std::abs(a - b) <= 1e-4f * std::max(std::abs(b), 1e-2f); };
    uint32_t hits = 0, samePrimitive = 0, ties = 0, anyMismatch = 0, failures = 0;
    std::ostringstream log;
    for (uint32_t i = 0; i < rayCount; ++i) {
        const TraceRay& ray = rays[i];
        vec3 o(ray.originTMax), d(ray.dir);
        float tMax = ray.originTMax.w;
        const TraceResult& g = gpuResults[i];
        bool gpuHit = g.primitive != gpu::NO_HIT;
        if (bool(g.anyHit) != gpuHit) {
            ++anyMismatch;
            log << "ray " << i << ": anyHit " << g.anyHit << " but closest " << (gpuHit ? "hit" : "missed") << ", "
                << describe(ray) << "\n";
        }
        auto reference = intersectBruteForce(scene, o, d, tMax);
        if (reference) ++hits;
        bool ok;
        if (bool(reference) != gpuHit) {
            ok = false;
        } else if (!reference) {
            ok = true;
        } else if (g.primitive >= bvh.primitives.size()) {
            ok = false;
        } else if (bvh.originalIndex[g.primitive] == reference->primitive) {
            ok = close(g.t, reference->t);
            samePrimitive += ok;
        } else {
            // A different primitive: acceptable only as a tie, i.e. the GPU's primitive is
            // also hit (on the CPU) at the same t within the tolerance.
            float t;
            glm::vec2 uv;
            ok = intersectPrimitive(scene[bvh.originalIndex[g.primitive]], o, d, kInf, t, uv) &&
                 close(t, reference->t) && close(g.t, reference->t);
            ties += ok;
        }
        if (!ok) {
            ++failures;
            log << "ray " << i << ": cpu " << (reference ? std::to_string(reference->primitive) : "miss") << " t="
                << (reference ? reference->t : 0.0f) << ", gpu "
                << (gpuHit && g.primitive < bvh.originalIndex.size() ? std::to_string(bvh.originalIndex[g.primitive])
                                                                    : "miss")
                << " t=" << g.t << ", " << describe(ray) << "\n";
        }
    }
    std::cout << "[ " << label << " ] " << rayCount << " rays, " << hits << " hit, " << samePrimitive
              << " same primitive, " << ties << " ties, " << failures << " disagreements, " << anyMismatch
              << " any-hit mismatches; "
              << "lavapipe " << gpuSeconds << " s (incl. pipeline compile)\n";
    if (failures || anyMismatch) std::ofstream(test::outputPath(label + "_mismatches.txt")) << log.str();
    EXPECT_GT(hits, rayCount / 4) << "most rays should hit something";
    EXPECT_EQ(anyMismatch, 0u) << "see build/test-output/" << label << "_mismatches.txt";
    EXPECT_EQ(failures, 0u) << "see build/test-output/" << label << "_mismatches.txt";
    EXPECT_LE(ties, hits / 1000 + 1) << "ties (distinct primitives at equal t) should be rare";
}

}  // namespace

// ---- (a) CPU BVH == CPU brute force ----------------------------------------------------

TEST(Bvh, CpuTraversalMatchesBruteForce) {
    Random rng(1234);
    struct Case {
        uint32_t triangles, spheres, quads;
        BvhOptions options;
    };
    const Case cases[] = {{2, 0, 0, {}},
                          {5, 3, 2, {}},
                          {200, 20, 20, {}},
                          {2000, 150, 150, {}},
                          {2000, 150, 150, {1, 16}},
                          {2000, 150, 150, {8, 4}},
                          {500, 0, 0, {2, 32}},
                          {0, 300, 0, {}},
                          {0, 0, 300, {}}};
    for (const Case& c : cases) {
        auto scene = randomScene(rng, c.triangles, c.spheres, c.quads);
        Bvh bvh = buildBvh(scene, c.options);
        auto rays = randomRays(rng, 3000, 14.0f, &scene);
        // Every third ray gets a finite tMax, so any-hit is also checked with short rays.
        for (size_t i = 0; i < rays.size(); i += 3) rays[i].originTMax.w = rng.uniform(0.0f, 15.0f);
        CpuComparison r = compareCpu(scene, bvh, rays);
        SCOPED_TRACE(testing::Message() << c.triangles << " triangles, " << c.spheres << " spheres, " << c.quads
                                        << " quads, leaf " << c.options.maxLeafSize << ", bins " << c.options.binCount);
        EXPECT_EQ(r.failures, 0u) << "first failing ray: " << r.firstFailure;
        EXPECT_GT(r.hits, rays.size() / 20) << "the scene should be hit by a fair share of rays";
        EXPECT_LE(r.ties, r.hits / 100 + 1) << "exact ties in t should be rare";
    }
}

// ---- (b) GPU traversal == CPU brute force ------------------------------------------------

TEST(Bvh, GpuTraversalMatchesCpuBruteForce) {
    Random rng(20240607);
    auto scene = randomScene(rng, 4000, 400, 400);
    Bvh bvh = buildBvh(scene);
    const uint32_t rayCount = 1u << 17;  // 131072
    // Origins inside and outside the scene's [-10, 10]^3; half the rays aimed at primitives.
    auto rays = randomRays(rng, rayCount, 16.0f, &scene);
    mixRayLengths(rng, bvh, rays, 20.0f);
    // Every way the kernel may read nodes (render/node_reads.h): the texel buffer (the
    // shader's default) and the storage buffer in loads of 16 and of 32 bytes.
    for (const auto& [specialization, reads, pairs] : everyNodeReads())
        expectGpuMatchesCpuBruteForce(scene, bvh, rays, specialization, "bvh_gpu_" + reads, pairs);
}

// (b') Primitives beside the tree (Bvh::besideCount): a floor whose box has most of the
// scene box's area and a sphere light by itself go beside it; a light of two triangles and
// the small shapes stay in it. Every query tests the two before the tree, on the CPU and on
// the GPU in every way it reads nodes; a kernel or a CPU traversal that skipped them misses
// the floor.
TEST(Bvh, PrimitivesBesideTheTreeMatchBruteForce) {
    Random rng(4711);
    auto scene = randomScene(rng, 400, 30, 30);  // in [-10, 10]^3 and a little beyond
    const uint32_t floorIndex = uint32_t(scene.size());
    scene.push_back(quad(vec3(-12, -11, -12), vec3(0, 0, 24), vec3(24, 0, 0)));
    const uint32_t lampIndex = uint32_t(scene.size());
    scene.push_back(sphere(vec3(0, 11, 0), 0.5f));
    scene.back().light = 0;
    for (int k = 0; k < 2; ++k) {  // one light of two triangles: its shadow rays end on either
        scene.push_back(triangle(vec3(3, 11, 3), vec3(4, 11, 3 + k), vec3(3 + k, 11, 4)));
        scene.back().light = 1;
    }
    Bvh bvh = buildBvh(scene);
    ASSERT_EQ(bvh.besideCount, 2u);
    EXPECT_EQ(bvh.besideFirst(), scene.size() - 2);
    EXPECT_EQ(bvh.originalIndex[bvh.besideFirst()], floorIndex);
    EXPECT_EQ(bvh.originalIndex[bvh.besideFirst() + 1], lampIndex);
    for (uint32_t i = 0; i < bvh.besideFirst(); ++i) EXPECT_NE(bvh.originalIndex[i], floorIndex);
    // The floor widens the scene's bounds beyond the tree's.
    EXPECT_EQ(bvhBounds(bvh).lo.y, -11.0f);
    EXPECT_GT(bvh.nodes.front().boundsMin.y, -11.0f);
    // The rule's limits: the largest box first, none where none may go, none in a scene of
    // fewer than BvhOptions::besideFrom primitives.
    BvhOptions one;
    one.maxBeside = 1;
    const Bvh onlyFloor = buildBvh(scene, one);
    ASSERT_EQ(onlyFloor.besideCount, 1u);
    EXPECT_EQ(onlyFloor.originalIndex.back(), floorIndex);
    BvhOptions none;
    none.maxBeside = 0;
    EXPECT_EQ(buildBvh(scene, none).besideCount, 0u);
    std::vector<gpu::Primitive> small(scene.end() - 40, scene.end());
    EXPECT_EQ(buildBvh(small).besideCount, 0u);

    auto rays = randomRays(rng, 1u << 15, 14.0f, &scene);
    mixRayLengths(rng, bvh, rays, 20.0f);
    uint32_t besideHits = 0;
    for (const TraceRay& ray : rays) {
        auto reference = intersectBruteForce(scene, vec3(ray.originTMax), vec3(ray.dir), ray.originTMax.w);
        besideHits += reference && (reference->primitive == floorIndex || reference->primitive == lampIndex);
    }
    EXPECT_GT(besideHits, rays.size() / 20) << "the floor should be the nearest hit of a fair share of rays";
    CpuComparison cpu = compareCpu(scene, bvh, rays);
    EXPECT_EQ(cpu.failures, 0u) << "first failing ray: " << cpu.firstFailure;
    for (const auto& [specialization, reads, pairs] : everyNodeReads())
        expectGpuMatchesCpuBruteForce(scene, bvh, rays, specialization, "bvh_beside_" + reads, pairs);
}

// (b'') The same with every primitive inline (shaders/geometry/inline_geometry.glsl): the
// kernel tests the specialization constants in their slots instead of traversing, and
// must find what the CPU finds (the leaf-order index each slot names). Both layouts the
// host makes: 48 random primitives (as many as the kernel declares) come as runs of eight
// in leaf order, 24 as subtrees of the BVH in padded groups, out of leaf order.
TEST(Bvh, InlineGeometryMatchesCpuBruteForce) {
    for (const uint32_t triangles : {uint32_t(INLINE_MAX_PRIMITIVES) - 16u, 8u}) {
        Random rng(777);
        auto scene = randomScene(rng, triangles, 8, 8, 3.0f);
        SCOPED_TRACE(scene.size());
        Bvh bvh = buildBvh(scene);
        const uint32_t rayCount = 1u << 14;
        auto rays = randomRays(rng, rayCount, 5.0f, &scene);
        mixRayLengths(rng, bvh, rays, 8.0f);
        KernelOptions options;
        options.inlineGeometry = inlineGeometryWords(bvh);
        bool reordered = false;
        for (uint32_t slot = 0; slot < options.inlineGeometry.slotCount(); ++slot) {
            const uint32_t word = options.inlineGeometry.slots[slot * INLINE_PRIMITIVE_WORDS];
            reordered = reordered || ((word & INLINE_SLOT_TYPE_MASK) != INLINE_SLOT_EMPTY &&
                                      word >> INLINE_SLOT_INDEX_SHIFT != slot);
        }
        EXPECT_EQ(reordered, scene.size() < INLINE_MAX_PRIMITIVES) << "not the layout this case is for";
        // The kernel gets a tree with no children, so only the inline tests can find a hit.
        Bvh hollow = bvh;
        hollow.wideNodes = buildBvh({}).wideNodes;
        expectGpuMatchesCpuBruteForce(scene, hollow, rays, options.specialization(), "inline_gpu");
    }
}

// ---- (c) Degenerate builds ---------------------------------------------------------------

TEST(Bvh, EmptySceneHasOneLeafThatNothingHits) {
    Bvh bvh = buildBvh({});
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.nodes[0].primCount, 0u);
    EXPECT_TRUE(bvh.primitives.empty());
    EXPECT_EQ(bvh.sahCost, 0.0f);
    EXPECT_EQ(bvhDepth(bvh), 0u);
    Random rng(7);
    auto rays = randomRays(rng, 1000, 5.0f);
    rays.push_back({glm::vec4(0, 0, 0, kInf), glm::vec4(1, 0, 0, 0)});  // zero direction components
    rays.push_back({glm::vec4(0, 0, 0, kInf), glm::vec4(0, 0, -1, 0)});
    for (const auto& ray : rays) {
        EXPECT_FALSE(intersectClosest(bvh, vec3(ray.originTMax), vec3(ray.dir), kInf));
        EXPECT_FALSE(intersectAny(bvh, vec3(ray.originTMax), vec3(ray.dir), kInf));
    }
    for (const auto& r : traceOnGpu(bvh, rays)) {
        EXPECT_EQ(r.primitive, gpu::NO_HIT);
        EXPECT_EQ(r.anyHit, 0u);
    }
}

namespace {
// Closest hits on CPU (BVH) and GPU must equal brute force for a small scene.
void expectAllAgree(const std::vector<gpu::Primitive>& scene, const Bvh& bvh, const std::vector<TraceRay>& rays) {
    CpuComparison cpu = compareCpu(scene, bvh, rays);
    EXPECT_EQ(cpu.failures, 0u) << cpu.firstFailure;
    auto gpuResults = traceOnGpu(bvh, rays);
    uint32_t failures = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        auto reference = intersectBruteForce(scene, vec3(rays[i].originTMax), vec3(rays[i].dir), rays[i].originTMax.w);
        const TraceResult& g = gpuResults[i];
        bool ok = bool(reference) == (g.primitive != gpu::NO_HIT) && g.anyHit == uint32_t(bool(reference));
        if (ok && reference)
            ok = std::abs(g.t - reference->t) <= 1e-4f * reference->t &&
                 (bvh.originalIndex[g.primitive] == reference->primitive || g.t == reference->t);
        if (!ok && failures++ == 0) {
            std::ostringstream s;
            s.precision(9);  // as describe(): enough digits to tell a float from its neighbours
            s << "gpu disagrees for " << describe(rays[i]) << ": brute force ";
            if (reference) s << "t=" << reference->t;
            else s << "no hit";
            s << ", gpu ";
            if (g.primitive != gpu::NO_HIT) s << "t=" << g.t;
            else s << "no hit";
            s << " any hit " << g.anyHit;
            ADD_FAILURE() << s.str();
        }
    }
    EXPECT_EQ(failures, 0u);
}
}  // namespace

TEST(Bvh, SinglePrimitiveIsOneLeaf) {
    Random rng(11);
    for (auto prim : {triangle(vec3(-1, -1, 0), vec3(1, -1, 0), vec3(0, 1, 0)), sphere(vec3(0.5f, 0, 0), 1.0f),
                      quad(vec3(-1, -1, 0.2f), vec3(2, 0, 0), vec3(0, 2, 0))}) {
        std::vector<gpu::Primitive> scene{prim};
        Bvh bvh = buildBvh(scene);
        ASSERT_EQ(bvh.nodes.size(), 1u);
        EXPECT_EQ(bvh.nodes[0].primCount, 1u);
        EXPECT_EQ(bvh.nodes[0].offset, 0u);
        EXPECT_FLOAT_EQ(bvh.sahCost, 1.0f);
        auto rays = randomRays(rng, 2000, 3.0f, &scene);
        // Rays along the axes (zero direction components) straight at the primitive.
        rays.push_back({glm::vec4(0, 0, 5, kInf), glm::vec4(0, 0, -1, 0)});
        rays.push_back({glm::vec4(0, 0, -5, kInf), glm::vec4(0, 0, 1, 0)});
        rays.push_back({glm::vec4(-5, 0.1f, 0.3f, kInf), glm::vec4(1, 0, 0, 0)});
        expectAllAgree(scene, bvh, rays);
    }
}

// The work counts feed the emitter-first rule (render/emitter_first.cpp): two triangles far
// apart are a root of two leaves, so a ray that hits one tests the root's node and one
// primitive, and a ray that leaves tests the root's node alone.
TEST(Bvh, TraversalWorkCountsNodesAndPrimitives) {
    std::vector<gpu::Primitive> scene{triangle(vec3(-6, -1, 0), vec3(-4, -1, 0), vec3(-5, 1, 0)),
                                      triangle(vec3(4, -1, 0), vec3(6, -1, 0), vec3(5, 1, 0))};
    Bvh bvh = buildBvh(scene);
    ASSERT_EQ(bvh.nodes.size(), 3u);
    TraversalWork work;
    ASSERT_TRUE(intersectClosest(bvh, vec3(-5, 0, 3), vec3(0, 0, -1), kInf, &work));
    EXPECT_EQ(work.nodes, 1u);
    EXPECT_EQ(work.primitives, 1u);
    // Counts add up over calls; a ray that misses both children stops at the root.
    EXPECT_FALSE(intersectClosest(bvh, vec3(-5, 0, 3), vec3(0, 0, 1), kInf, &work));
    EXPECT_EQ(work.nodes, 2u);
    EXPECT_EQ(work.primitives, 1u);
}

TEST(Bvh, CoincidentCentroidsSplitByMedian) {
    // Nested spheres and centred quads: every bounding box has the same centre, so no
    // binning plane separates anything and the builder must halve ranges instead.
    std::vector<gpu::Primitive> scene;
    vec3 c(1, 2, 3);
    for (int i = 0; i < 60; ++i) scene.push_back(sphere(c, 0.0625f * float(i + 1)));  // dyadic: exact centres
    Random rng(99);
    for (int i = 0; i < 60; ++i) {
        // Axis-aligned with dyadic sides, so that the box centres are exactly c.
        int axis = i % 3;
        vec3 u(0), v(0);
        u[axis] = 0.25f * float(2 + i % 13);
        v[(axis + 1) % 3] = 0.25f * float(3 + i % 7);
        scene.push_back(quad(c - 0.5f * (u + v), u, v));
    }
    Bvh bvh = buildBvh(scene);
    EXPECT_GT(bvh.nodes.size(), 1u);
    EXPECT_LE(bvhDepth(bvh), 6u) << "median splits of 120 primitives into leaves of 4";
    for (const auto& node : bvh.nodes) EXPECT_LE(node.primCount, 4u);
    auto rays = randomRays(rng, 4000, 6.0f);
    for (auto& ray : rays) ray.originTMax += glm::vec4(c, 0);
    expectAllAgree(scene, bvh, rays);
}

// ---- (c2) The wide nodes the traversal reads -----------------------------------------------

// Every binary leaf is the child of exactly one wide node, with its range, inside a decoded
// box that contains its binary box; every wide node but the root is the child of exactly one
// node; interior nodes have 2 to 4 children; the wide tree is no deeper than the binary one
// (the traversal stack's bound). Breaking the quantizer's outward rounding fails the
// containment check, a lost or doubled subtree the counts.
TEST(Bvh, WideNodesHoldEveryLeafOnceInsideItsBox) {
    Random rng(77);
    for (int round = 0; round < 3; ++round) {
        auto scene = round == 2 ? randomScene(rng, 3000, 0, 0, 1000.0f) : randomScene(rng, 300, 30, 30);
        auto rays = randomRays(rng, 3000, round == 2 ? 600.0f : 6.0f, &scene);
        if (round == 1) {
            // Far from the world origin, where floats are coarse next to the boxes' sizes.
            const vec3 shift(1e4f, -3e3f, 7e2f);
            for (auto& p : scene) {
                p.p0 += shift;
                if ((p.typeAndNormals & gpu::PRIM_TYPE_MASK) == gpu::PRIM_TRIANGLE) {
                    p.p1 += shift;
                    p.p2 += shift;
                }
            }
            for (auto& ray : rays) ray.originTMax += glm::vec4(shift, 0.0f);
        }
        Bvh bvh = buildBvh(scene);
        const auto& wide = bvh.wideNodes;
        ASSERT_FALSE(wide.empty());
        std::map<std::pair<uint32_t, uint32_t>, std::pair<vec3, vec3>> binaryLeaves;  // range -> box
        for (const auto& n : bvh.nodes)
            if (n.primCount > 0) binaryLeaves[{n.offset, n.primCount}] = {n.boundsMin, n.boundsMax};
        std::vector<uint32_t> nodeUses(wide.size(), 0);
        nodeUses[0] = 1;
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> leafUses;
        uint32_t deepest = 0;
        std::vector<std::pair<uint32_t, uint32_t>> stack{{0u, 0u}};  // (wide node, depth)
        while (!stack.empty()) {
            auto [index, depth] = stack.back();
            stack.pop_back();
            deepest = std::max(deepest, depth);
            uint32_t children = 0;
            for (uint32_t c = 0; c < WIDE_NODE_ARITY; ++c) {
                WideChildBox box = decodeWideChild(wide[index], c);
                if (!box.exists) continue;
                ++children;
                uint32_t count = box.ref >> BVH_COUNT_SHIFT, offset = box.ref & gpu::BVH_OFFSET_MASK;
                if (count > 0) {
                    auto found = binaryLeaves.find({offset, count});
                    ASSERT_NE(found, binaryLeaves.end()) << "node " << index << " child " << c;
                    ++leafUses[{offset, count}];
                    for (int axis = 0; axis < 3; ++axis) {
                        EXPECT_LE(box.lo[axis], found->second.first[axis]) << "node " << index << " child " << c;
                        EXPECT_GE(box.hi[axis], found->second.second[axis]) << "node " << index << " child " << c;
                    }
                } else {
                    ASSERT_LT(offset, wide.size());
                    ASSERT_GT(offset, index) << "children follow their parents";
                    ++nodeUses[offset];
                    stack.push_back({offset, depth + 1});
                }
            }
            EXPECT_GE(children, index == 0 ? 1u : 2u);
        }
        EXPECT_LE(deepest, bvhDepth(bvh));
        EXPECT_EQ(leafUses.size(), binaryLeaves.size());
        for (const auto& [range, uses] : leafUses) EXPECT_EQ(uses, 1u);
        for (uint32_t uses : nodeUses) EXPECT_EQ(uses, 1u);
        expectAllAgree(scene, bvh, rays);
    }
}

namespace {

void allCovers(const std::vector<gpu::BvhNode>& nodes, uint32_t n, uint32_t k, std::vector<std::vector<uint32_t>>& out);

// Every way to cover interior node n's two children with at most k nodes, j of them or
// fewer under its left child (wide.cpp's collapse, enumerated).
void splitCovers(const std::vector<gpu::BvhNode>& nodes, uint32_t n, uint32_t k, uint32_t j,
                 std::vector<std::vector<uint32_t>>& out) {
    std::vector<std::vector<uint32_t>> left, right;
    allCovers(nodes, n + 1, j, left);
    allCovers(nodes, nodes[n].offset, k - j, right);
    for (const auto& a : left)
        for (const auto& b : right) {
            out.push_back(a);
            out.back().insert(out.back().end(), b.begin(), b.end());
        }
}

// Every way to cover binary node n's subtree with at most k nodes: n itself, or covers of
// its two children.
void allCovers(const std::vector<gpu::BvhNode>& nodes, uint32_t n, uint32_t k,
               std::vector<std::vector<uint32_t>>& out) {
    out.push_back({n});
    if (nodes[n].primCount > 0) return;
    for (uint32_t j = 1; j < k; ++j) splitCovers(nodes, n, k, j, out);
}

// The least total area of wide nodes for interior node n's subtree, by trying every cover
// of its two children at every wide node.
double leastWideArea(const std::vector<gpu::BvhNode>& nodes, uint32_t n, std::map<uint32_t, double>& memo) {
    if (auto found = memo.find(n); found != memo.end()) return found->second;
    std::vector<std::vector<uint32_t>> covers;
    for (uint32_t j = 1; j < WIDE_NODE_ARITY; ++j) splitCovers(nodes, n, WIDE_NODE_ARITY, j, covers);
    double best = DBL_MAX;
    for (const auto& cover : covers) {
        double cost = 0.0;
        for (uint32_t c : cover)
            if (nodes[c].primCount == 0) cost += leastWideArea(nodes, c, memo);
        best = std::min(best, cost);
    }
    return memo[n] = double(nodeArea(nodes[n])) + best;
}

}  // namespace

TEST(Bvh, OptimalCollapseHasTheLeastWideNodeArea) {
    // Small trees: the optimal rule's area is the least of every collapse, enumerated, and
    // no more than the greedy rule's. Larger ones: no more than the greedy rule's.
    Random rng(2024);
    for (int round = 0; round < 12; ++round) {
        const bool small = round < 8;
        Bvh bvh = buildBvh(small ? randomScene(rng, 20 + 4 * round, 3, 3) : randomScene(rng, 3000, 50, 50),
                           BvhOptions{.maxLeafSize = small ? 2u : 4u});
        ASSERT_EQ(bvh.nodes[0].primCount, 0u);
        const double optimal = wideNodeArea(bvh.nodes, WideCollapse::Optimal);
        const double greedy = wideNodeArea(bvh.nodes, WideCollapse::Greedy);
        EXPECT_LE(optimal, greedy * (1.0 + 1e-12)) << "round " << round;
        if (small) {
            std::map<uint32_t, double> memo;
            EXPECT_NEAR(optimal, leastWideArea(bvh.nodes, 0, memo), 1e-9 * optimal) << "round " << round;
        }
    }
}

TEST(Bvh, LargestLeavesSurviveTheStackPacking) {
    // A wide node packs a child as offset | primCount << BVH_COUNT_SHIFT: leaves of
    // BVH_MAX_LEAF_SIZE primitives must come back whole. Nested spheres around one centre
    // cannot be split by SAH, so they fill leaves up to the (clamped) size limit.
    std::vector<gpu::Primitive> scene;
    vec3 c(-2, 1, 0.5f);
    for (int i = 0; i < 248; ++i) scene.push_back(sphere(c, 0.03125f * float(i + 1)));  // 248 = 8 x 31
    Bvh bvh = buildBvh(scene, {1000, 16});
    uint32_t largest = 0;
    for (const auto& node : bvh.nodes) largest = std::max(largest, node.primCount);
    EXPECT_EQ(largest, gpu::BVH_MAX_LEAF_SIZE) << "maxLeafSize is clamped to BVH_MAX_LEAF_SIZE";
    Random rng(31);
    auto rays = randomRays(rng, 3000, 8.0f);
    for (auto& ray : rays) ray.originTMax += glm::vec4(c, 0);
    expectAllAgree(scene, bvh, rays);
}

TEST(Bvh, TraversalRoundsAddUpToItsWork) {
    // penumbra_bench --lanes replays TraversalWork::rounds: one entry per round of the outer
    // loop (nodes << 16 | primitives), for both queries and both kinds of stack entry, the
    // any-hit's cut-short last round too, and nothing recorded where no rounds are asked
    // for. A round starts at a node popped from the stack, or, with child entries, perhaps
    // at a leaf, whose round then tests no node.
    Random rng(41);
    auto scene = randomScene(rng, 600, 60, 60);
    Bvh bvh = buildBvh(scene);
    auto rays = randomRays(rng, 400, 16.0f, &scene);
    size_t anyHits = 0, leafRounds = 0;
    for (const auto& ray : rays)
        for (bool any : {false, true})
            for (StackEntries entries : {StackEntries::Children, StackEntries::Nodes}) {
                std::vector<uint32_t> rounds;
                TraversalWork work;
                work.rounds = &rounds;
                const vec3 o(ray.originTMax), d(ray.dir);
                const bool hit = any ? intersectAny(bvh, o, d, kInf, &work, entries)
                                     : bool(intersectClosest(bvh, o, d, kInf, &work, entries));
                anyHits += any && hit;
                uint32_t nodes = 0, primitives = 0;
                for (uint32_t r : rounds) {
                    EXPECT_NE(r, 0u) << "every round tests a node or a leaf";
                    if (entries == StackEntries::Nodes) {
                        EXPECT_GE(r >> 16, 1u) << "every round tests a node";
                    }
                    leafRounds += (r >> 16) == 0;
                    nodes += r >> 16;
                    primitives += r & 0xffffu;
                }
                EXPECT_EQ(nodes, work.nodes);
                EXPECT_EQ(primitives, work.primitives);
                TraversalWork unrecorded;
                if (any) intersectAny(bvh, o, d, kInf, &unrecorded, entries);
                else intersectClosest(bvh, o, d, kInf, &unrecorded, entries);
                EXPECT_EQ(unrecorded.nodes, work.nodes);
                EXPECT_EQ(unrecorded.rounds, nullptr);
            }
    EXPECT_GT(anyHits, 200u) << "rays that stop at their first hit are the case to cover";
    EXPECT_GT(leafRounds, 0u) << "child entries that are leaves are a case to cover";
}

TEST(Bvh, StackDepthIsTheLongestPathsInteriorNodes) {
    // No traversal whose stack entries are nodes may hold more than wideStackDepth entries,
    // nor one that pushes child references more than childStackDepth (which sizes the
    // "_address" kernels' stacks, render/traversal_stacks.h), and neither may be larger than
    // one can. Rays from the common centre of nested spheres start inside every box, so
    // nothing is culled and every interior node on every path pushes the children it does
    // not take first: some ray holds exactly wideStackDepth nodes, and more than that many
    // children, so a child stack of wideStackDepth entries would clamp some away. (The GPU
    // comparison below runs with childStackDepth entries; run with wideStackDepth it still
    // passes on these rays, as the entries lost lie behind the closest hit. So the
    // "_address" kernel's own stack use is read back, from a stack with room to spare: it
    // must be what the CPU counts, closest-hit queries being the deeper of the two.)
    EXPECT_EQ(wideStackDepth(buildBvh({}).wideNodes), 1u);
    EXPECT_EQ(wideStackDepth(buildBvh({sphere(vec3(0), 1.0f)}).wideNodes), 1u);
    std::vector<gpu::Primitive> nested;
    const vec3 c(0.5f, -1, 2);
    for (int i = 0; i < 300; ++i) nested.push_back(sphere(c, 0.0625f * float(i + 1)));
    Random rng(12);
    const Bvh nestedBvh = buildBvh(nested, {2, 16});
    const uint32_t depth = wideStackDepth(nestedBvh.wideNodes);
    EXPECT_GE(depth, 4u) << "300 primitives in leaves of at most 2 take several levels";
    EXPECT_EQ(childStackDepth(nestedBvh.wideNodes), 3 * depth);
    uint32_t deepestNodes = 0, deepestChildren = 0;
    std::vector<TraceRay> fromCentre;
    for (int i = 0; i < 200; ++i) {
        TraversalWork nodes, children;
        vec3 dir = rng.unitVector();
        intersectClosest(nestedBvh, c, dir, kInf, &nodes, StackEntries::Nodes);
        intersectClosest(nestedBvh, c, dir, kInf, &children, StackEntries::Children);
        deepestNodes = std::max(deepestNodes, nodes.deepestStack);
        deepestChildren = std::max(deepestChildren, children.deepestStack);
        fromCentre.push_back({glm::vec4(c, kInf), glm::vec4(dir, 0)});
    }
    EXPECT_EQ(deepestNodes, depth);
    EXPECT_GT(deepestChildren, depth);
    EXPECT_LE(deepestChildren, childStackDepth(nestedBvh.wideNodes));
    expectAllAgree(nested, nestedBvh, fromCentre);
    if (deviceReadsNodesThroughAddresses()) {
        EXPECT_EQ(gpuStackHighWater(nestedBvh, fromCentre, childStackDepth(nestedBvh.wideNodes) + 8), deepestChildren);
    }
    const auto scene = randomScene(rng, 400, 40, 40, 6.0f);
    const Bvh bvh = buildBvh(scene);
    deepestNodes = deepestChildren = 0;
    const std::vector<TraceRay> random = randomRays(rng, 2000, 8.0f);
    for (const TraceRay& ray : random) {
        TraversalWork nodes, children;
        intersectClosest(bvh, vec3(ray.originTMax), vec3(ray.dir), kInf, &nodes, StackEntries::Nodes);
        intersectClosest(bvh, vec3(ray.originTMax), vec3(ray.dir), kInf, &children, StackEntries::Children);
        deepestNodes = std::max(deepestNodes, nodes.deepestStack);
        deepestChildren = std::max(deepestChildren, children.deepestStack);
    }
    EXPECT_GT(deepestNodes, 1u);
    EXPECT_LE(deepestNodes, wideStackDepth(bvh.wideNodes));
    EXPECT_GT(deepestChildren, 1u);
    EXPECT_LE(deepestChildren, childStackDepth(bvh.wideNodes));
    if (deviceReadsNodesThroughAddresses()) {
        EXPECT_EQ(gpuStackHighWater(bvh, random, childStackDepth(bvh.wideNodes) + 8), deepestChildren);
    }
}

TEST(Bvh, NonFiniteRaysMissAndTerminate) {
    // NaN can make every slab test pass: the traversal must reject such rays before its
    // loop, on both sides (a hang fails by timeout).
    const float nan = std::nanf(""), inf = kInf * 2.0f;
    std::vector<TraceRay> rays;
    for (glm::vec4 o : {glm::vec4(nan, 0, 0, kInf), glm::vec4(0, 0, 5, kInf), glm::vec4(inf, 0, 0, kInf)})
        for (glm::vec4 d : {glm::vec4(0, 0, -1, 0), glm::vec4(nan, nan, nan, 0), glm::vec4(0, -inf, 0, 0)})
            if (!(o.z == 5 && d.z == -1)) rays.push_back({o, d});
    Random rng(8);
    for (const auto& scene : {std::vector<gpu::Primitive>{}, randomScene(rng, 50, 5, 5, 4.0f)}) {
        Bvh bvh = buildBvh(scene);
        for (const TraceRay& ray : rays) {
            EXPECT_FALSE(intersectClosest(bvh, vec3(ray.originTMax), vec3(ray.dir), kInf)) << describe(ray);
            EXPECT_FALSE(intersectAny(bvh, vec3(ray.originTMax), vec3(ray.dir), kInf)) << describe(ray);
        }
        for (const auto& [specialization, reads, pairs] : everyNodeReads())
            for (const TraceResult& r : traceOnGpu(bvh, rays, specialization, pairs)) {
                SCOPED_TRACE(reads);
                EXPECT_EQ(r.primitive, gpu::NO_HIT);
                EXPECT_EQ(r.anyHit, 0u);
            }
    }
}

// ---- (d) Large builds: structure, SAH cost, depth bound --------------------------------

namespace {
// Every primitive in exactly one leaf, children inside their parent, leaves small enough.
void expectWellFormed(const Bvh& bvh, size_t primitiveCount, uint32_t maxLeafSize) {
    ASSERT_EQ(bvh.primitives.size(), primitiveCount);
    std::vector<uint32_t> sorted = bvh.originalIndex;
    std::sort(sorted.begin(), sorted.end());
    for (uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i) << "originalIndex is not a permutation";
    ASSERT_LE(bvh.nodes.size(), 2 * primitiveCount);
    std::vector<uint32_t> covered(primitiveCount, 0);
    std::vector<uint32_t> stack{0};
    uint32_t visited = 0;
    while (!stack.empty()) {
        uint32_t index = stack.back();
        stack.pop_back();
        ++visited;
        const auto& node = bvh.nodes[index];
        if (node.primCount > 0) {
            ASSERT_LE(node.primCount, maxLeafSize);
            for (uint32_t i = node.offset; i < node.offset + node.primCount; ++i) {
                ++covered[i];
                vec3 lo, hi;
                primitiveBounds(bvh.primitives[i], lo, hi);
                ASSERT_TRUE(glm::all(glm::greaterThanEqual(lo, node.boundsMin)) &&
                            glm::all(glm::lessThanEqual(hi, node.boundsMax)));
            }
            continue;
        }
        for (uint32_t child : {index + 1, node.offset}) {
            ASSERT_LT(child, bvh.nodes.size());
            ASSERT_GT(child, index) << "depth-first order: children follow their parent";
            ASSERT_TRUE(glm::all(glm::greaterThanEqual(bvh.nodes[child].boundsMin, node.boundsMin)) &&
                        glm::all(glm::lessThanEqual(bvh.nodes[child].boundsMax, node.boundsMax)));
            stack.push_back(child);
        }
    }
    EXPECT_EQ(visited, bvh.nodes.size()) << "every node is reachable exactly once";
    // Every primitive in exactly one leaf, except those beside the tree, in none.
    for (uint32_t i = 0; i < primitiveCount; ++i)
        ASSERT_EQ(covered[i], i < bvh.besideFirst() ? 1u : 0u) << "primitive " << i << " of " << primitiveCount;
}
}  // namespace

TEST(Bvh, LargeBuildHasSaneCostAndBoundedDepth) {
    Random rng(5);
    // 200k small triangles in clusters of varying density, like scanned or tessellated models.
    std::vector<gpu::Primitive> scene;
    for (int cluster = 0; cluster < 50; ++cluster) {
        vec3 centre = rng.inBox(-100, 100);
        float radius = rng.uniform(1.0f, 20.0f);
        for (int i = 0; i < 4000; ++i) {
            vec3 c = centre + radius * rng.inBox(-1, 1);
            float size = 0.02f * radius;
            scene.push_back(
                triangle(c + size * rng.inBox(-1, 1), c + size * rng.inBox(-1, 1), c + size * rng.inBox(-1, 1)));
        }
    }
    Bvh bvh = buildBvh(scene);
    expectWellFormed(bvh, scene.size(), 4);
    uint32_t depth = bvhDepth(bvh);
    std::cout << "[ bvh large ] " << scene.size() << " triangles: " << bvh.nodes.size() << " nodes, depth " << depth
              << ", SAH cost " << bvh.sahCost << "\n";
    EXPECT_LE(depth, uint32_t(BVH_MAX_DEPTH));
    EXPECT_GE(depth, 16u) << "200k primitives in leaves of <= 4 need at least 16 levels";
    // A tree that does its job costs a small multiple of log2(N) box tests, not O(N): the
    // single-leaf cost would be 200000. (Measured about 60 for this scene.)
    EXPECT_GT(bvh.sahCost, 1.0f);
    EXPECT_LT(bvh.sahCost, 150.0f);
    // The same primitives in one leaf each cost more (more nodes), never less, than leaves of 4.
    Bvh fine = buildBvh(scene, {1, 16});
    expectWellFormed(fine, scene.size(), 1);
    EXPECT_LE(bvhDepth(fine), uint32_t(BVH_MAX_DEPTH));
}

TEST(Bvh, AdversarialSceneKeepsDepthWithinStackBound) {
    // Triangles at geometrically growing distances: each SAH split peels off only the few
    // farthest ones, which without the depth guard gives a tree ~N/2 deep.
    std::vector<gpu::Primitive> scene;
    float x = 1.0f;
    for (int i = 0; i < 1500; ++i, x *= 1.05f) {
        float s = 0.01f * x;
        scene.push_back(triangle(vec3(x, 0, 0), vec3(x + s, 0, 0), vec3(x, s, s)));
    }
    Bvh bvh = buildBvh(scene, {1, 16});
    expectWellFormed(bvh, scene.size(), 1);
    EXPECT_LE(bvhDepth(bvh), uint32_t(BVH_MAX_DEPTH));
    // Rays along the row of triangles, from the origin; CPU and GPU agree with brute force.
    Random rng(3);
    std::vector<TraceRay> rays;
    for (int i = 0; i < 2000; ++i) {
        float target = std::pow(1.05f, rng.uniform(0.0f, 1500.0f));
        vec3 p(target * 1.001f, target * 0.004f, target * 0.004f);
        vec3 o = rng.inBox(-1, 1);
        rays.push_back({glm::vec4(o, kInf), glm::vec4(glm::normalize(p - o), 0)});
    }
    expectAllAgree(scene, bvh, rays);
}

// ---- (e) Self-intersection: tests/bvh_surface.comp --------------------------------------

namespace {
struct SurfaceCase {
    glm::vec4 origin, dir, outLocal;
};
struct SurfaceResult {
    uint32_t firstPrimitive, selfHit, secondPrimitive;
    float offset;
    glm::vec4 position, normal, shading;
};
static_assert(sizeof(SurfaceCase) == 48 && sizeof(SurfaceResult) == 64);
}  // namespace

TEST(Bvh, SecondaryRaysNeverReHitTheirOwnSurface) {
    Random rng(42);
    const float scales[] = {1e-3f, 1e-2f, 1e-1f, 1.0f, 1e1f, 1e2f, 1e3f};
    std::vector<gpu::Primitive> scene;
    std::vector<float> scaleOf;
    std::vector<gpu::TriangleNormals> shadingNormals;
    for (float s : scales) {
        for (int far = 0; far < 2; ++far) {
            // Near the world origin, and far from it (where a small primitive has few bits).
            vec3 base = far ? vec3(700, -300, 500) : vec3(0);
            for (int i = 0; i < 30; ++i) {
                vec3 c = base + s * rng.inBox(-20, 20);
                scene.push_back(triangle(c + s * rng.inBox(-1, 1), c + s * rng.inBox(-1, 1), c + s * rng.inBox(-1, 1)));
                if (i % 2) {
                    // Every other triangle carries vertex normals, all three the same unit
                    // vector, so the interpolated shading normal must be exactly that vector.
                    vec3 m = rng.unitVector();
                    shadingNormals.push_back({glm::vec4(m, 0), glm::vec4(m, 0), glm::vec4(m, 0)});
                    scene.back().typeAndNormals |= uint32_t(shadingNormals.size()) << 2;
                }
                scene.push_back(sphere(base + s * rng.inBox(-20, 20), s * rng.uniform(0.3f, 1.0f)));
                vec3 q = base + s * rng.inBox(-20, 20);
                scene.push_back(quad(q, s * rng.uniform(0.3f, 2.0f) * rng.unitVector(),
                                     s * rng.uniform(0.3f, 2.0f) * rng.unitVector()));
                for (int k = 0; k < 3; ++k) scaleOf.push_back(s);
            }
        }
    }
    Bvh bvh = buildBvh(scene);

    // Per primitive: several first rays at random points of it, each followed by second
    // rays in the outward hemisphere (and, for flat primitives, through to the other side),
    // with cos(theta) down to 1e-4: grazing rays are where offsets fail first.
    std::vector<SurfaceCase> cases;
    std::vector<uint32_t> target;
    for (uint32_t p = 0; p < scene.size(); ++p) {
        const gpu::Primitive& prim = scene[p];
        uint32_t type = prim.typeAndNormals & gpu::PRIM_TYPE_MASK;
        float s = scaleOf[p];
        for (int k = 0; k < 24; ++k) {
            vec3 point, normal;
            if (type == gpu::PRIM_TRIANGLE) {
                float a = std::sqrt(rng.uniform(0.01f, 0.99f)), b = rng.uniform(0.01f, 0.99f);
                point = (1 - a) * prim.p0 + a * (1 - b) * prim.p1 + a * b * prim.p2;
                normal = glm::normalize(glm::cross(prim.p1 - prim.p0, prim.p2 - prim.p0));
            } else if (type == gpu::PRIM_QUAD) {
                point = prim.p0 + rng.uniform(0.01f, 0.99f) * prim.p1 + rng.uniform(0.01f, 0.99f) * prim.p2;
                normal = glm::normalize(glm::cross(prim.p1, prim.p2));
            } else {
                normal = rng.unitVector();
                point = prim.p0 + prim.p1.x * normal;
            }
            if (type != gpu::PRIM_SPHERE && rng.uniform() < 0.5f) normal = -normal;
            vec3 w = rng.unitVector();
            if (glm::dot(w, normal) < 0.2f) w = glm::normalize(w + (1.2f - glm::dot(w, normal)) * normal);
            vec3 origin = point + 3.0f * s * w;
            float cosTheta = std::pow(10.0f, rng.uniform(-4.0f, 0.0f));
            float phi = rng.uniform(0.0f, 6.2831853f), sinTheta = std::sqrt(1 - cosTheta * cosTheta);
            float side = (type == gpu::PRIM_SPHERE || rng.uniform() < 0.5f) ? 1.0f : -1.0f;
            cases.push_back({glm::vec4(origin, 0), glm::vec4(glm::normalize(point - origin), 0),
                             glm::vec4(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta, side)});
            target.push_back(p);
        }
    }

    const auto results = runSceneKernel<SurfaceResult>("tests/bvh_surface", bvh, shadingNormals, cases);

    uint32_t valid = 0, selfHits = 0, largeOffsets = 0, badNormals = 0;
    std::ostringstream log;
    log.precision(9);
    for (size_t i = 0; i < cases.size(); ++i) {
        const SurfaceResult& r = results[i];
        if (r.firstPrimitive == gpu::NO_HIT || bvh.originalIndex[r.firstPrimitive] != target[i]) continue;
        ++valid;
        vec3 p(r.position);
        float magnitude = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
        // Wächter-Binder moves each coordinate by at most 256 ulps (or 2^-16 near zero).
        bool offsetOk = r.offset <= 256.0f * 1.2e-7f * 1.8f * magnitude + 3e-5f;
        // Geometric normal: the unflipped front normal of SCENE_FORMAT.md; shading normal:
        // the vertex normal where given, else the geometric normal.
        const gpu::Primitive& prim = scene[target[i]];
        uint32_t type = prim.typeAndNormals & gpu::PRIM_TYPE_MASK;
        vec3 front = type == gpu::PRIM_TRIANGLE ? glm::normalize(glm::cross(prim.p1 - prim.p0, prim.p2 - prim.p0))
                     : type == gpu::PRIM_QUAD   ? glm::normalize(glm::cross(prim.p1, prim.p2))
                                                : glm::normalize(p - prim.p0);
        uint32_t normalsIndex = prim.typeAndNormals >> 2;
        vec3 shading = normalsIndex ? vec3(shadingNormals[normalsIndex - 1].n0) : front;
        // For spheres the expected normal comes from the float position p, whose rounding
        // (a few ulps of |p|) is not small against a tiny radius far from the origin.
        float tolerance = 1e-4f + (type == gpu::PRIM_SPHERE ? 4.0f * 1.2e-7f * magnitude / prim.p1.x : 0.0f);
        bool normalOk = glm::length(vec3(r.normal) - front) < tolerance &&
                        glm::length(vec3(r.shading) - shading) < tolerance;
        selfHits += r.selfHit;
        largeOffsets += !offsetOk;
        badNormals += !normalOk;
        if (r.selfHit || !offsetOk || !normalOk)
            log << "case " << i << " primitive " << target[i] << " type "
                << (scene[target[i]].typeAndNormals & gpu::PRIM_TYPE_MASK) << " scale " << scaleOf[target[i]]
                << ": selfHit " << r.selfHit << " at t=" << r.position.w << ", offset " << r.offset << ", p=(" << p.x
                << "," << p.y << "," << p.z << "), out=(" << cases[i].outLocal.x << "," << cases[i].outLocal.y << ","
                << cases[i].outLocal.z << "," << cases[i].outLocal.w << ")\n";
    }
    std::cout << "[ bvh offset ] " << cases.size() << " cases, " << valid << " hit their target, " << selfHits
              << " self-hits, " << largeOffsets << " large offsets, " << badNormals << " wrong normals\n";
    if (selfHits || largeOffsets || badNormals)
        std::ofstream(test::outputPath("bvh_self_intersection.txt")) << log.str();
    EXPECT_GT(valid, cases.size() * 7 / 10) << "most first rays should reach their target primitive";
    EXPECT_EQ(selfHits, 0u) << "see build/test-output/bvh_self_intersection.txt";
    EXPECT_EQ(largeOffsets, 0u);
    EXPECT_EQ(badNormals, 0u);
}
