// penumbra_bench: render throughput and BVH statistics for benchmark scenes.
// For each scene: BVH build time and SAH cost, the bytes per triangle (or other primitive)
// of the geometry the kernels read (BVH nodes, primitives and shading normals), scene upload and first-pass time (llvmpipe
// compiles shaders lazily on the first dispatch) reported separately, then the render
// time as the median of --runs full renders, million pixel samples per second, and million
// rays per second: rays per sample are counted in separate, untimed passes by a
// ray-counting variant of the kernel (Renderer::countRays), so the timed renders run the
// kernel that users get. cpu_s is the median CPU time of a render (all threads), and
// cpu_Ms/s the samples per CPU second: steadier than wall time on a shared machine.
// --count-rays prints only the rays per sample of each scene (no timing), for
// tools/mitsuba/mitsuba_compare.py. Scenes are files, or "procedural:N" for a displaced sphere of about N triangles on a floor.
// --write-mesh N FILE writes that sphere's mesh as JSON, for tools/scenes/make_bench_scenes.py.
// --low-spp breaks down where a render of 1, 2, 4 and 8 spp at half the film size (the
// time-to-error comparison of tools/bench/bench-mitsuba) spends its time: Renderer::renderAll as
// `penumbra render` times it, its submissions, the same passes in one submission (one
// dispatch adding every sample), an empty submission (the fixed cost of one), and one
// submission of one dispatch per pass or per eighth of a pass (the first pass's strips,
// render/pass_bands.h): what separate dispatches cost.
// --samples-per-dispatch renders each scene's spp (rounded up to a power of two, at least
// 16) in one submission of dispatches that add K = 1, 2, 4, ... spp samples to each pixel,
// alternating over --runs rounds, and prints the medians of samples per CPU second and
// their ratio to K = 1: what a dispatch gains by adding more samples to each pixel (an
// invocation's fixed cost spread wider, a pixel's last reads still in the caches), the
// reason for render/pass_bands.h's sweeps.
// --spp N renders every scene at N samples per pixel (throughput does not depend on spp).
// --emitter-first rule|off|exact: how BRDF-sampled rays find emitters (render/emitter_first.h,
// EmitterFirst; default rule), so that one build measures both paths on any scene.
// --node-reads device|texels|storage|storage32|address: where the traversal reads BVH nodes from
// (render/node_reads.h; default device, the driver's choice), likewise.
// --lanes prints, per scene, the node steps and primitive tests of camera, AO and shadow rays, and
// the share of a SIMD group's lane iterations that do work for them, for the kernel's loop
// and another, and for other groupings of the rays (laneUse below).
// --brdf-ray-fates prints, per scene, what the emitter-first rule sees (the fractions of
// probe rays that hit an emitter, something else, or nothing, and the mean work of their
// closest-hit traversal) and what it chooses for the kernel the scene gets (inline or not).
// --instructions, run under valgrind --tool=callgrind (tools/bench/bench-instructions does that),
// has callgrind dump the instructions of every pass of each scene, in one submission (after
// the kernel is compiled), to a file of its own: a count that repeats exactly from run to run, where
// timings on a shared machine vary by 10-30%.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <sys/resource.h>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define PENUMBRA_HAVE_CALLGRIND 1
#else
#define PENUMBRA_HAVE_CALLGRIND 0
#endif

#include "bvh/bvh.h"
#include "bvh/lane_replay.h"
#include "gpu/context.h"
#include "gpu/gpu_timer.h"
#include "render/pass_bands.h"
#include "render/probe_rays.h"
#include "render/renderer.h"
#include "scene/load.h"

using namespace penumbra;
using Clock = std::chrono::steady_clock;

namespace {

// `value` as one of the named `choices` of `option`, into `out`; false (with a message naming
// the choices) for any other value.
template <class Mode>
bool parseChoice(const char* option, const std::string& value,
                 std::initializer_list<std::pair<const char*, Mode>> choices, Mode& out) {
    std::string names;
    for (const auto& [name, mode] : choices) {
        if (value == name) {
            out = mode;
            return true;
        }
        names += names.empty() ? name : std::string(", ") + name;
    }
    std::fprintf(stderr, "penumbra_bench: %s takes %s, not %s\n", option, names.c_str(), value.c_str());
    return false;
}

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// CPU seconds used by this process so far, all threads (llvmpipe's workers included), user
// and system. On a shared machine other processes lengthen wall time far more than they
// lengthen the CPU time a render needs, so A/B comparisons can use it (tools/bench/bench-ab
// --metric cpu).
double processCpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto seconds = [](timeval t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// The displaced-sphere bench mesh, defined only here (tools/scenes/make_bench_scenes.py asks for
// it with --write-mesh): a sphere of `rings` x 2*rings quads (two triangles each, one in
// the two polar rows) with a bumpy radius, counter-clockwise seen from outside.
Shape displacedSphere(int triangles) {
    int rings = std::max(4, int(std::sqrt(triangles / 4.0)));
    Shape mesh;
    mesh.type = ShapeType::Mesh;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= 2 * rings; ++j) {
            float theta = float(M_PI) * i / rings, phi = 2 * float(M_PI) * j / (2 * rings);
            glm::vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            float r = 0.8f * (1.0f + 0.08f * std::sin(13 * theta) * std::sin(11 * phi) +
                              0.03f * std::sin(57 * theta + 3 * phi));
            mesh.positions.push_back(glm::vec3(0, 0.85f, 0) + r * d);
        }
    auto at = [&](int i, int j) { return uint32_t(i * (2 * rings + 1) + j); };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < 2 * rings; ++j) {
            if (i > 0) mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
            if (i < rings - 1) mesh.indices.insert(mesh.indices.end(), {at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
        }
    return mesh;
}

// --write-mesh N FILE: the mesh as {"positions": [...], "indices": [...]} (5 decimals).
int writeMesh(int triangles, const char* path) {
    Shape mesh = displacedSphere(triangles);
    FILE* f = std::fopen(path, "w");
    if (!f) {
        std::fprintf(stderr, "penumbra_bench: cannot write %s\n", path);
        return 1;
    }
    std::fputs("{\"positions\":[", f);
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        std::fprintf(f, "%s%.5f,%.5f,%.5f", i ? "," : "", mesh.positions[i].x, mesh.positions[i].y,
                     mesh.positions[i].z);
    std::fputs("],\"indices\":[", f);
    for (size_t i = 0; i < mesh.indices.size(); ++i) std::fprintf(f, "%s%u", i ? "," : "", mesh.indices[i]);
    std::fputs("]}\n", f);
    return std::fclose(f) == 0 ? 0 : 1;
}

// An ambient-occlusion scene of the displaced sphere on a floor ("procedural:N").
Scene proceduralScene(int triangles) {
    Scene scene;
    scene.name = "procedural";
    scene.camera.eye = {0, 1.2f, 3.5f};
    scene.camera.target = {0, 0.8f, 0};
    scene.film = {512, 384};
    scene.sampler.spp = 16;
    scene.integrator.type = IntegratorType::AmbientOcclusion;
    scene.materials.push_back({"default", MaterialType::Diffuse, glm::vec3(0.8f), glm::vec3(0.0f), 0.0f});
    Shape mesh = displacedSphere(triangles);
    scene.shapes.push_back(std::move(mesh));
    Shape floor;
    floor.type = ShapeType::Quad;
    floor.origin = {-5, 0, -5};
    floor.edgeU = {0, 0, 10};
    floor.edgeV = {10, 0, 0};
    scene.shapes.push_back(floor);
    return scene;
}

Scene benchScene(const std::string& name) {
    return name.rfind("procedural:", 0) == 0 ? proceduralScene(std::stoi(name.substr(11))) : loadScene(name);
}

// Rays per pixel sample, counted over a few untimed passes (they vary little between
// passes; four pin them to well under 1%). The samples land in the accumulation.
double raysPerSample(Renderer& renderer, const Scene& scene) {
    const uint32_t passes = std::min<uint32_t>(scene.sampler.spp, 4);
    const double pixels = double(scene.film.width) * scene.film.height;
    return double(renderer.countRays(passes)) / (pixels * passes);
}

// The primitives in the world: the scene's own and every instance's (render/instance_arrays.h).
size_t triangleCount(const Scene& scene) {
    auto count = [](const std::vector<Shape>& shapes) {
        size_t n = 0;
        for (const Shape& s : shapes) n += s.type == ShapeType::Mesh ? s.indices.size() / 3 : 1;
        return n;
    };
    size_t n = count(scene.shapes);
    for (const Instance& instance : scene.instances) n += count(scene.instancedGroups.at(instance.group).shapes);
    return n;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// --samples-per-dispatch (see the top of this file).
void samplesPerDispatch(const gpu::Context& context, Scene scene, int runs) {
    uint32_t spp = 16;
    while (spp < scene.sampler.spp && spp < PassBands::kMaxPassesPerBand) spp *= 2;
    scene.sampler.spp = spp;
    Renderer renderer(context, scene);
    renderer.compileKernel();
    std::vector<uint32_t> ks;
    for (uint32_t k = 1; k <= spp; k *= 2) ks.push_back(k);
    std::vector<std::vector<double>> rates(ks.size());
    const double samples = double(scene.film.width) * scene.film.height * scene.sampler.spp;
    for (int r = 0; r < runs; ++r)
        for (size_t i = 0; i < ks.size(); ++i) {
            renderer.reset();
            const double cpu0 = processCpuSeconds();
            context.submitAndWait([&](VkCommandBuffer cmd) {
                for (uint32_t first = 0; first < scene.sampler.spp; first += ks[i])
                    renderer.recordPasses(cmd, first, ks[i], 0, scene.film.height);
            });
            rates[i].push_back(samples / (processCpuSeconds() - cpu0) * 1e-6);
        }
    std::printf("%s, %u spp, Msamples per CPU second (median of %d), by samples per dispatch:\n", scene.name.c_str(),
                scene.sampler.spp, runs);
    const double base = median(rates[0]);
    for (size_t i = 0; i < ks.size(); ++i)
        std::printf("  K = %2u: %7.3f  (%.2fx K = 1)\n", ks[i], median(rates[i]), median(rates[i]) / base);
    std::fflush(stdout);
}

// --low-spp: per spp, medians over `runs` of: renderAll (what penumbra:render_seconds
// measures), its submissions, all passes recorded in one submission, and one empty
// submission. The kernel is compiled before anything is timed, as `penumbra render` does.
void lowSppBreakdown(const gpu::Context& context, Scene scene, int runs) {
    scene.film.width = std::max(1u, scene.film.width / 2);
    scene.film.height = std::max(1u, scene.film.height / 2);
    std::printf("%s at %ux%u: seconds, median of %d\n", scene.name.c_str(), scene.film.width, scene.film.height, runs);
    std::printf("%5s %12s %12s %14s %14s %14s %14s\n", "spp", "renderAll", "submissions", "one_submission",
                "empty_submit", "pass_dispatch", "strip_dispatch");
    for (uint32_t spp : {1u, 2u, 4u, 8u}) {
        scene.sampler.spp = spp;
        Renderer renderer(context, scene);
        renderer.compileKernel();
        std::vector<double> all, one, empty, strips, passes;
        int submissions = 0;
        for (int r = 0; r < runs; ++r) {
            renderer.reset();
            submissions = 0;
            auto t0 = Clock::now();
            renderer.renderAll([&](const RenderProgress&) { ++submissions; });
            all.push_back(secondsSince(t0));
            renderer.reset();
            t0 = Clock::now();
            context.submitAndWait(
                [&](VkCommandBuffer cmd) { renderer.recordPasses(cmd, 0, spp, 0, scene.film.height); });
            one.push_back(secondsSince(t0));
            t0 = Clock::now();
            context.submitAndWait([](VkCommandBuffer) {});
            empty.push_back(secondsSince(t0));
            renderer.reset();
            t0 = Clock::now();
            context.submitAndWait([&](VkCommandBuffer cmd) {
                for (uint32_t s = 0; s < spp; ++s) renderer.recordPasses(cmd, s, 1, 0, scene.film.height);
            });
            passes.push_back(secondsSince(t0));
            renderer.reset();
            t0 = Clock::now();
            const uint32_t h = scene.film.height;
            context.submitAndWait([&](VkCommandBuffer cmd) {
                for (uint32_t s = 0; s < spp; ++s)
                    for (uint32_t k = 0; k < 8; ++k)
                        renderer.recordPasses(cmd, s, 1, h * k / 8, h * (k + 1) / 8 - h * k / 8);
            });
            strips.push_back(secondsSince(t0));
        }
        std::printf("%5u %12.4f %12d %14.4f %14.4f %14.4f %14.4f\n", spp, median(all), submissions, median(one),
                    median(empty), median(passes), median(strips));
        std::fflush(stdout);
    }
    // The fixed costs apart from the work: 32 bands of one 8-pixel tile, each in its own
    // submission (with the device timer renderAll records) or all in one submission.
    Renderer renderer(context, scene);
    const gpu::GpuTimer timer(context);
    std::vector<double> perSubmission, perDispatch;
    constexpr int kBands = 32;
    for (int r = 0; r < runs; ++r) {
        auto t0 = Clock::now();
        for (int i = 0; i < kBands; ++i)
            context.submitAndWait([&](VkCommandBuffer cmd) {
                timer.start(cmd);
                renderer.recordPasses(cmd, uint32_t(i), 1, 0, 1, 0, PassBands::kTile);
                timer.stop(cmd);
            });
        perSubmission.push_back(secondsSince(t0) / kBands);
        t0 = Clock::now();
        context.submitAndWait([&](VkCommandBuffer cmd) {
            for (int i = 0; i < kBands; ++i) renderer.recordPasses(cmd, uint32_t(i), 1, 0, 1, 0, PassBands::kTile);
        });
        perDispatch.push_back(secondsSince(t0) / kBands);
    }
    std::printf("one tile (8 pixel samples): %.5f s per submission, %.5f s per dispatch within one submission\n",
                median(perSubmission), median(perDispatch));
}

// --lanes: how much of llvmpipe's SIMD width the traversals use. llvmpipe runs a row of
// eight invocations of the 8x8 workgroup (eight adjacent pixels of a tile,
// integrators/kernel_common.glsl) in one SIMD group, and a loop runs until its last lane is
// done. The CPU mirror (bvh/traverse.cpp) takes the kernel's steps and records each ray's
// rounds of the outer loop (nodes its descent tested, primitives its leaf tested);
// lane_replay.h replays them in lockstep, in the kernel's while-while form and in the
// if-if form. Rays: one per pixel centre, and from each hit one unbounded any-hit ray in a
// cosine-distributed direction (the normal plus a uniform point on the sphere), an AO ray.
// The rows after the first two group the same kinds of rays otherwise:
// - "regrouped": the AO rays in eights by their direction's octant and their origin's Morton
//   code (10 bits an axis, over the origins' bounds), as a wavefront renderer could regroup
//   them before tracing; that also fills the lanes a missed camera ray leaves idle.
// - "4x2": a SIMD group on a block of 4 x 2 pixels instead of a row of 8.
// - "K queued": each lane traces K samples of its pixel (jittered camera rays and their AO
//   rays), one after another, taking its next ray as soon as its last one is done: what
//   refilling finished lanes would use of the width at best.
uint32_t spreadBits10(uint32_t v) {  // bits 0-9 of v to bits 0, 3, 6, ... 27
    v &= 0x3ffu;
    v = (v | v << 16) & 0x030000ffu;
    v = (v | v << 8) & 0x0300f00fu;
    v = (v | v << 4) & 0x030c30c3u;
    v = (v | v << 2) & 0x09249249u;
    return v;
}

// Where an AO ray starts and which octant it heads into (the regrouping's keys).
struct AoRayStart {
    glm::vec3 origin;
    uint32_t octant;
};

// A camera ray through `film` and, where it hits, an AO ray from the hit, their rounds
// appended to `camera` and `ao`. Returns the AO ray's start, none where the camera ray missed.
std::optional<AoRayStart> traceProbeSample(const Bvh& bvh, const gpu::RenderParams& p, glm::vec2 film,
                                           std::mt19937& rng, LaneRays& camera, LaneRays& ao) {
    std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
    TraversalWork work;
    work.rounds = &camera.rounds;
    ++camera.rays;
    const auto hit = probeCameraRay(bvh, p, film, &work);
    if (!hit) return std::nullopt;
    glm::vec3 r;
    do r = glm::vec3(uniform(rng), uniform(rng), uniform(rng));
    while (glm::dot(r, r) > 1.0f || glm::dot(r, r) < 1e-6f);
    const glm::vec3 aoDir = glm::normalize(hit->normal + glm::normalize(r));
    TraversalWork aoWork;
    aoWork.rounds = &ao.rounds;
    ++ao.rays;
    intersectAny(bvh, hit->rayOrigin, aoDir, 3.4e38f, &aoWork);
    return AoRayStart{hit->rayOrigin, uint32_t(aoDir.x < 0) | uint32_t(aoDir.y < 0) << 1 | uint32_t(aoDir.z < 0) << 2};
}

void printLaneUse(const std::string& scene, const std::string& kind, const LaneUse& use) {
    const double rays = std::max(use.rays, 1.0);
    std::printf("%-28s %-16s %9.0f %9.2f %9.2f %8.3f %8.3f %8.3f %8.3f\n", scene.c_str(), kind.c_str(), use.rays,
                use.nodes / rays, use.primitives / rays, use.whileNodeShare(), use.whilePrimitiveShare(),
                use.ifNodeShare(), use.ifPrimitiveShare());
}

// The lanes that traced a ray (an AO lane whose camera ray missed traced none, and idles).
std::vector<const LaneRays*> groupOf(const std::vector<LaneRays>& lanes) {
    std::vector<const LaneRays*> group;
    for (const LaneRays& lane : lanes)
        if (!lane.rounds.empty() || lane.rays > 0) group.push_back(&lane);
    return group;
}

// Camera rays through the pixel centres and shadow rays, from each camera hit, a segment to a
// uniform point on the scene's first quad or sphere light (where the surface faces it), in
// the tree as built and in one with no primitive beside it (bvh/bvh.h, Bvh::besideCount).
// Rows of eight pixels.
void laneUseBesideTheTree(const std::string& name, const Scene& scene, const SceneArrays& arrays,
                          const gpu::RenderParams& p) {
    const Shape* light = nullptr;
    for (const Shape& shape : scene.shapes)
        if (!light && shape.isEmitter() && (shape.type == ShapeType::Quad || shape.type == ShapeType::Sphere))
            light = &shape;
    if (!light) return;
    BvhOptions nothingBeside;
    nothingBeside.maxBeside = 0;
    const SceneArrays inTree = buildSceneArrays(scene, nothingBeside);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    LaneUse asBuilt, allInTree, cameraInTree;
    uint32_t blocked = 0;
    for (uint32_t y = 0; y < p.height; ++y)
        for (uint32_t x0 = 0; x0 < p.width; x0 += 8) {
            std::vector<LaneRays> built(std::min(8u, p.width - x0)), tree(built.size()), camera(built.size());
            for (uint32_t i = 0; i < built.size(); ++i) {
                const glm::vec2 film((x0 + i + 0.5f) / p.width, (y + 0.5f) / p.height);
                TraversalWork cameraWork;
                cameraWork.rounds = &camera[i].rounds;
                ++camera[i].rays;
                probeCameraRay(inTree.bvh, p, film, &cameraWork);
                const auto hit = probeCameraRay(arrays.bvh, p, film);
                if (!hit) continue;
                glm::vec3 target;
                if (light->type == ShapeType::Quad) {
                    target = light->origin + uniform(rng) * light->edgeU + uniform(rng) * light->edgeV;
                } else {
                    const float z = 2.0f * uniform(rng) - 1.0f, phi = 6.2831853f * uniform(rng);
                    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
                    target = light->center + light->radius * glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
                }
                const glm::vec3 toLight = target - hit->rayOrigin;
                const float distance = glm::length(toLight);
                if (!(distance > 0.0f) || glm::dot(toLight, hit->normal) <= 0.0f) continue;
                // Short of the light, as integrators/direct.comp's visible() stops.
                const float tMax = distance * (1.0f - 1e-4f);
                for (auto [lanes, bvh] : {std::pair{&built, &arrays.bvh}, std::pair{&tree, &inTree.bvh}}) {
                    TraversalWork work;
                    work.rounds = &(*lanes)[i].rounds;
                    ++(*lanes)[i].rays;
                    const bool occluded = intersectAny(*bvh, hit->rayOrigin, toLight / distance, tMax, &work);
                    blocked += occluded && bvh == &arrays.bvh;
                }
            }
            cameraInTree.addGroup(groupOf(camera));
            if (!groupOf(built).empty()) asBuilt.addGroup(groupOf(built));
            if (!groupOf(tree).empty()) allInTree.addGroup(groupOf(tree));
        }
    printLaneUse(name, "camera, in tree", cameraInTree);
    printLaneUse(name, "shadow", asBuilt);
    printLaneUse(name, "shadow, in tree", allInTree);
    std::printf("%-28s %-16s %9u of %.0f shadow rays blocked; %u primitives beside the tree\n", name.c_str(), "",
                blocked, asBuilt.rays, arrays.bvh.besideCount);
}

void laneUse(const std::string& name) {
    Scene scene = benchScene(name);
    SceneArrays arrays = buildSceneArrays(scene);
    const gpu::RenderParams p = makeRenderParams(scene, arrays);
    const Bvh& bvh = arrays.bvh;
    std::mt19937 rng(1);
    auto centre = [&](uint32_t x, uint32_t y) { return glm::vec2((x + 0.5f) / p.width, (y + 0.5f) / p.height); };

    // Rows of eight pixels, one ray of each kind per lane; the AO rays kept for regrouping.
    LaneUse camera, ao, regrouped;
    std::vector<std::pair<AoRayStart, LaneRays>> aoRays;
    for (uint32_t y = 0; y < p.height; ++y)
        for (uint32_t x0 = 0; x0 < p.width; x0 += 8) {
            std::vector<LaneRays> cameraLanes(std::min(8u, p.width - x0)), aoLanes(cameraLanes.size());
            for (uint32_t i = 0; i < cameraLanes.size(); ++i) {
                const auto start = traceProbeSample(bvh, p, centre(x0 + i, y), rng, cameraLanes[i], aoLanes[i]);
                if (start) aoRays.push_back({*start, aoLanes[i]});
            }
            camera.addGroup(groupOf(cameraLanes));
            // Lanes whose camera ray missed idle in the AO group: it is still eight wide.
            const std::vector<const LaneRays*> aoGroup = groupOf(aoLanes);
            if (!aoGroup.empty()) ao.addGroup(aoGroup);
        }
    if (!aoRays.empty()) {
        glm::vec3 lo(3.4e38f), hi(-3.4e38f);
        for (const auto& [start, lane] : aoRays) {
            lo = glm::min(lo, start.origin);
            hi = glm::max(hi, start.origin);
        }
        const glm::vec3 scale = 1023.0f / glm::max(hi - lo, glm::vec3(1e-30f));
        std::vector<std::pair<uint64_t, const LaneRays*>> keyed;  // (octant, Morton code), ray
        for (const auto& [start, lane] : aoRays) {
            const glm::uvec3 q =
                glm::uvec3(glm::clamp((start.origin - lo) * scale, glm::vec3(0.0f), glm::vec3(1023.0f)));
            const uint64_t morton = spreadBits10(q.x) | spreadBits10(q.y) << 1 | spreadBits10(q.z) << 2;
            keyed.push_back({uint64_t(start.octant) << 32 | morton, &lane});
        }
        std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (size_t i = 0; i < keyed.size(); i += 8) {
            std::vector<const LaneRays*> group;
            for (size_t j = i; j < std::min(i + 8, keyed.size()); ++j) group.push_back(keyed[j].second);
            regrouped.addGroup(group);
        }
    }
    printLaneUse(name, "camera", camera);
    printLaneUse(name, "ao", ao);
    printLaneUse(name, "ao, regrouped", regrouped);
    laneUseBesideTheTree(name, scene, arrays, p);

    // Blocks of 4 x 2 pixels.
    LaneUse blockCamera, blockAo;
    for (uint32_t y0 = 0; y0 < p.height; y0 += 2)
        for (uint32_t x0 = 0; x0 < p.width; x0 += 4) {
            std::vector<LaneRays> cameraLanes, aoLanes;
            for (uint32_t i = 0; i < 8; ++i) {
                const uint32_t x = x0 + i % 4, y = y0 + i / 4;
                if (x >= p.width || y >= p.height) continue;
                cameraLanes.emplace_back();
                aoLanes.emplace_back();
                traceProbeSample(bvh, p, centre(x, y), rng, cameraLanes.back(), aoLanes.back());
            }
            blockCamera.addGroup(groupOf(cameraLanes));
            const std::vector<const LaneRays*> aoGroup = groupOf(aoLanes);
            if (!aoGroup.empty()) blockAo.addGroup(aoGroup);
        }
    printLaneUse(name, "camera, 4x2", blockCamera);
    printLaneUse(name, "ao, 4x2", blockAo);

    // Rows of eight pixels, K jittered samples per lane, traced one after another.
    std::uniform_real_distribution<float> jitter(0.0f, 1.0f);
    for (uint32_t K : {4u, 16u}) {
        LaneUse queuedCamera, queuedAo;
        for (uint32_t y = 0; y < p.height; ++y)
            for (uint32_t x0 = 0; x0 < p.width; x0 += 8) {
                std::vector<LaneRays> cameraLanes(std::min(8u, p.width - x0)), aoLanes(cameraLanes.size());
                for (uint32_t i = 0; i < cameraLanes.size(); ++i)
                    for (uint32_t k = 0; k < K; ++k) {
                        const float jx = jitter(rng), jy = jitter(rng);
                        const glm::vec2 film((x0 + i + jx) / p.width, (y + jy) / p.height);
                        traceProbeSample(bvh, p, film, rng, cameraLanes[i], aoLanes[i]);
                    }
                queuedCamera.addGroup(groupOf(cameraLanes));
                const std::vector<const LaneRays*> aoGroup = groupOf(aoLanes);
                if (!aoGroup.empty()) queuedAo.addGroup(aoGroup);
            }
        printLaneUse(name, "camera, " + std::to_string(K) + " queued", queuedCamera);
        printLaneUse(name, "ao, " + std::to_string(K) + " queued", queuedAo);
    }
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 5;
    bool countOnly = false, lowSpp = false, perDispatch = false, fatesOnly = false, lanesOnly = false,
         instructions = false;
    uint32_t spp = 0;
    EmitterFirst emitterFirst = EmitterFirst::Rule;
    InlineGeometry inlineGeometry = InlineGeometry::Rule;
    NodeReads nodeReads = NodeReads::Device;
    std::vector<std::string> scenes;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--count-rays")) countOnly = true;
        else if (!std::strcmp(argv[i], "--low-spp")) lowSpp = true;
        else if (!std::strcmp(argv[i], "--samples-per-dispatch")) perDispatch = true;
        else if (!std::strcmp(argv[i], "--brdf-ray-fates")) fatesOnly = true;
        else if (!std::strcmp(argv[i], "--lanes")) lanesOnly = true;
        else if (!std::strcmp(argv[i], "--instructions")) instructions = true;
        else if (!std::strcmp(argv[i], "--spp") && i + 1 < argc) spp = uint32_t(std::max(1, std::atoi(argv[++i])));
        else if (!std::strcmp(argv[i], "--emitter-first") && i + 1 < argc) {
            if (!parseChoice("--emitter-first", argv[++i],
                             {{"rule", EmitterFirst::Rule}, {"off", EmitterFirst::Off}, {"exact", EmitterFirst::Exact}},
                             emitterFirst))
                return 2;
        } else if (!std::strcmp(argv[i], "--inline") && i + 1 < argc) {
            if (!parseChoice("--inline", argv[++i], {{"rule", InlineGeometry::Rule}, {"off", InlineGeometry::Off}},
                             inlineGeometry))
                return 2;
        } else if (!std::strcmp(argv[i], "--node-reads") && i + 1 < argc) {
            if (!parseChoice("--node-reads", argv[++i],
                             {{"device", NodeReads::Device},
                              {"texels", NodeReads::Texels},
                              {"storage", NodeReads::Storage},
                              {"storage32", NodeReads::Storage32},
                              {"address", NodeReads::Address}},
                             nodeReads))
                return 2;
        } else if (!std::strcmp(argv[i], "--write-mesh") && i + 2 < argc)
            return writeMesh(std::atoi(argv[i + 1]), argv[i + 2]);
        else scenes.push_back(argv[i]);
    }
    if (runs < 1) {
        std::fprintf(stderr, "penumbra_bench: --runs needs a positive count\n");
        return 2;
    }
    if (scenes.empty()) {
        std::fprintf(stderr,
                     "usage: penumbra_bench [--runs N] [--spp N] [--emitter-first rule|off|exact] [--inline rule|off]\n"
                     "                      [--node-reads device|texels|storage|storage32|address]\n"
                     "                      [--count-rays | --low-spp | --samples-per-dispatch | --brdf-ray-fates | "
                     "--lanes | --instructions]\n"
                     "                      SCENE|procedural:N ...\n"
                     "       penumbra_bench --write-mesh N FILE\n");
        return 2;
    }
    try {
        if (lanesOnly) {
            // Shares of the SIMD width: node steps and primitive tests, in the while-while
            // loop (the kernel's) and in an if-if loop (lane_replay.h).
            std::printf("%-28s %-16s %9s %9s %9s %8s %8s %8s %8s\n", "scene", "rays", "count", "nodes/ray", "prims/ray",
                        "ww node", "ww prim", "ii node", "ii prim");
            for (const std::string& name : scenes) laneUse(name);
            return 0;
        }
        gpu::Context context;
        if (perDispatch) {
            for (const std::string& name : scenes) {
                Scene scene = benchScene(name);
                if (spp > 0) scene.sampler.spp = spp;
                samplesPerDispatch(context, scene, runs);
            }
            return 0;
        }
        if (lowSpp) {
            for (const std::string& name : scenes) lowSppBreakdown(context, benchScene(name), runs);
            return 0;
        }
        if (fatesOnly) {
            std::printf("%-28s %8s %8s %8s %8s %6s %6s\n", "scene", "emitter", "other", "escape", "work", "exact",
                        "pays");
            for (const std::string& name : scenes) {
                Scene scene = benchScene(name);
                SceneArrays arrays = buildSceneArrays(scene);
                BrdfRayFates f = brdfRayFates(scene, arrays);
                std::printf(
                    "%-28s %8.3f %8.3f %8.3f %8.1f %6d %6d\n", name.c_str(), f.emitter, f.other, f.escape,
                    f.closestHitWork, int(emitterFirstExact(scene.integrator, arrays)),
                    int(makeKernelOptions(scene, arrays, EmitterFirst::Rule, InlineGeometry::Rule).emitterFirstLights >
                        0));
            }
            return 0;
        }
        if (instructions) {
#if PENUMBRA_HAVE_CALLGRIND
            if (!RUNNING_ON_VALGRIND) {
                std::fprintf(stderr,
                             "penumbra_bench: --instructions runs under valgrind --tool=callgrind "
                             "(tools/bench/bench-instructions)\n");
                return 2;
            }
            for (const std::string& name : scenes) {
                Scene scene = benchScene(name);
                if (spp > 0) scene.sampler.spp = spp;
                Renderer renderer(context, scene);
                renderer.setEmitterFirst(emitterFirst);
                renderer.setInlineGeometry(inlineGeometry);
                renderer.setNodeReads(nodeReads);
                renderer.compileKernel();
                // Zeroing and dumping cover every thread (llvmpipe's workers run the kernel);
                // collection on and off would cover this thread alone. All passes go in one
                // submission over whole rows: renderAll sizes its submissions by the time
                // they take, so its split (and the partly filled tiles at a split's ends)
                // would vary from run to run.
                CALLGRIND_ZERO_STATS;
                context.submitAndWait([&](VkCommandBuffer cmd) {
                    renderer.recordPasses(cmd, 0, scene.sampler.spp, 0, scene.film.height);
                });
                CALLGRIND_DUMP_STATS_AT(name.c_str());
                std::printf("%s samples %.0f\n", name.c_str(),
                            double(scene.film.width) * scene.film.height * scene.sampler.spp);
            }
            return 0;
#else
            std::fprintf(stderr,
                         "penumbra_bench: built without valgrind/callgrind.h (apt-get install valgrind, "
                         "then rebuild) for --instructions\n");
            return 2;
#endif
        }
        if (countOnly) {
            for (const std::string& name : scenes) {
                Scene scene = benchScene(name);
                Renderer renderer(context, scene);
                renderer.setEmitterFirst(emitterFirst);
                renderer.setInlineGeometry(inlineGeometry);
                renderer.setNodeReads(nodeReads);
                std::printf("%s %.4f\n", name.c_str(), raysPerSample(renderer, scene));
            }
            return 0;
        }
        std::printf("device: %s\n", context.info().name.c_str());
        std::printf("%-28s %10s %9s %9s %9s %9s %10s %10s %9s %9s %9s %9s %9s\n", "scene", "prims", "bvh_s", "sah",
                    "upload_s", "first_s", "render_s", "Msamples/s", "rays/spl", "Mrays/s", "bytes/prim", "cpu_s",
                    "cpu_Ms/s");
        for (const std::string& name : scenes) {
            Scene scene = benchScene(name);
            if (spp > 0) scene.sampler.spp = spp;
            auto t0 = Clock::now();
            SceneArrays arrays = buildSceneArrays(scene);
            double bvhSeconds = secondsSince(t0);
            t0 = Clock::now();
            Renderer renderer(context, scene);
            renderer.setEmitterFirst(emitterFirst);
            renderer.setInlineGeometry(inlineGeometry);
            renderer.setNodeReads(nodeReads);
            double upload = secondsSince(t0);
            t0 = Clock::now();
            context.submitAndWait([&](VkCommandBuffer cmd) { renderer.recordPasses(cmd, 0, 1, 0, scene.film.height); });
            double first = secondsSince(t0);
            std::vector<double> times, cpuTimes;
            for (int r = 0; r < runs; ++r) {
                renderer.reset();
                t0 = Clock::now();
                double cpu0 = processCpuSeconds();
                renderer.renderAll();
                times.push_back(secondsSince(t0));
                cpuTimes.push_back(processCpuSeconds() - cpu0);
            }
            std::sort(times.begin(), times.end());
            std::sort(cpuTimes.begin(), cpuTimes.end());
            double median = times[times.size() / 2];
            double cpuMedian = cpuTimes[cpuTimes.size() / 2];
            double samples = double(scene.film.width) * scene.film.height * scene.sampler.spp;
            renderer.reset();
            double rays = raysPerSample(renderer, scene);
            size_t prims = triangleCount(scene);
            std::printf("%-28s %10zu %9.3f %9.2f %9.3f %9.3f %10.3f %10.3f %9.3f %9.2f %9.1f %9.3f %9.3f\n",
                        name.c_str(), prims, bvhSeconds, arrays.bvh.sahCost, upload, first, median,
                        samples / median * 1e-6, rays, samples * rays / median * 1e-6,
                        double(geometryBytes(arrays)) / double(std::max<size_t>(prims, 1)), cpuMedian,
                        samples / cpuMedian * 1e-6);
            std::fflush(stdout);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
