// What every integrator kernel shares: the render parameters, the accumulation buffer,
// the per-pass constants, camera rays (box filter over the pixel) and the guarded
// accumulation that keeps NaN/Inf out of the sums.
#ifndef PENUMBRA_KERNEL_COMMON_GLSL
#define PENUMBRA_KERNEL_COMMON_GLSL

#include "shared/types.h"
#include "common/math.glsl"
#include "common/rng.glsl"
#include "geometry/ray_count.glsl"
#include "integrators/aov_sums.glsl"

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;

layout(std140, binding = BINDING_PARAMS) uniform Params { RenderParams params; };
layout(std430, binding = BINDING_ACCUM) restrict buffer Accumulation { AccumSum accum[]; };
layout(std430, binding = BINDING_ACCUM_COMPENSATION) restrict buffer Compensation {
    AccumCompensation accumCompensation[];
};
layout(push_constant) uniform Pass { PassConstants pass; };
// The kernels' atomic counters: the rays traced, when counting, the tile queue's next
// pixel (main, below), which the host sets to 0 before each dispatch that uses it
// (render/tile_queue.h), and the invocations whose loops the driver cut short (main).
layout(std430, binding = BINDING_COUNTERS) restrict buffer Counters {
    uint rayCount;
    uint nextQueuedPixel;
    uint loopsCut;
};

// Whether the driver has cut this invocation's loops short (render/loop_budget.h): lavapipe
// before Mesa 25 gives a SIMD group's run 65535 loop iterations, all loops together, and
// then ends every loop at the end of its current iteration, silently. From then on every
// loop runs its body once, so this one, of LOOP_PROBE_TRIPS trips (a push constant, which
// the compiler cannot count), runs once. The budget only runs down, so all that was done
// before a check that finds the loops whole was done whole.
bool loopsWereCut() {
    if (kLoopsMayBeCut == 0u) return false;
    uint trips = 0u;
    for (uint i = 0u; i < pass.loopProbeTrips; ++i) ++trips;
    return trips != pass.loopProbeTrips;
}

// The first sample a pass adds to a pixel whose sums are `sum`: the pass's first, or, where
// the driver may cut loops short, the pixel's own next one (its sample count). A pixel that
// an earlier pass left short then takes up its samples where it stopped, and its sums are
// the same, bit for bit, as if nothing had been cut.
uint firstSampleOf(AccumSum sum) { return kLoopsMayBeCut != 0u ? sum.count : pass.sampleIndex; }

// The primitives the BVH's traversal tests before the tree (geometry/bvh.glsl).
uvec2 bvhBesideRange() { return uvec2(params.besideFirst, params.besideCount); }
// What camera rays pass to the traversal as `ignore` (geometry/bvh.glsl): the primitive
// beside the tree that none of them can meet, if any.
uvec2 cameraRayIgnores() { return uvec2(NO_HIT, params.cameraOutOfView); }

#ifdef PENUMBRA_NODE_ADDRESS
// Where the "_address" kernels read the BVH's nodes from, and where this invocation keeps
// its traversal stacks (geometry/bvh.glsl, invocationStack): BVH_STACKS_PER_INVOCATION of
// stackDepth entries from entry i * BVH_STACKS_PER_INVOCATION * stackDepth for invocation i
// of the dispatch (render/traversal_stacks.h keeps the dispatches within the buffer).
uvec2 bvhNodeAddress() { return uvec2(pass.nodeAddressLow, pass.nodeAddressHigh); }
uvec2 bvhStackAddress() { return uvec2(pass.stackAddressLow, pass.stackAddressHigh); }
uint bvhStackDepth() { return pass.stackDepth; }
uint bvhStackInvocation() {
    uvec3 size = gl_NumWorkGroups * gl_WorkGroupSize;
    return gl_GlobalInvocationID.x + size.x * (gl_GlobalInvocationID.y + size.y * gl_GlobalInvocationID.z);
}
#endif

// Pixel `local` of the band (relative to its first row and column), or false when it lies
// outside the film or the band's rows. The columns are bounded by the film alone: a band's
// run of columns is whole tiles or ends at the film's edge (Renderer::recordPasses).
bool bandPixel(uvec2 local, out uvec2 pixel) {
    pixel = uvec2(local.x + pass.firstColumn, local.y + pass.firstRow);
    return pixel.x < params.width && local.y < pass.rowCount && pixel.y < params.height;
}

// Pixel `index` of the band's tiles in queue order: tile by tile, tileColumns to a row, and
// within a tile row by row, so that the eight lanes of a SIMD group, which take eight
// numbers in a row, render a row of a tile together, as with one workgroup per tile
// (llvmpipe runs gl_LocalInvocationID.x 0-7 of one y together).
uvec2 queuedPixel(uint index) {
    uint tile = index / uint(TILE_PIXELS), within = index % uint(TILE_PIXELS);
    uint tileRow = tile / pass.tileColumns, tileColumn = tile % pass.tileColumns;
    return uvec2(tileColumn, tileRow) * uint(TILE_SIZE) + uvec2(within % uint(TILE_SIZE), within / uint(TILE_SIZE));
}

// The random stream of (pixel, sample): absolute index sampleOffset + sampleIndex, drawn
// by the scene's sampler.
Rng pixelRng(uvec2 pixel, uint sampleIndex) {
    return makeRng(pixel.y * params.width + pixel.x, params.sampleOffset + sampleIndex, params.seed, kSampler);
}

// Pinhole camera; `jitter` in [0,1)^2 spreads samples uniformly over the pixel (box
// filter). Pixel (0,0) is the top left of the image.
void cameraRay(uvec2 pixel, vec2 jitter, out vec3 origin, out vec3 dir) {
    vec2 film = (vec2(pixel) + jitter) / vec2(params.width, params.height);
    float x = (2.0 * film.x - 1.0) * params.aspect * params.tanHalfFovY;
    float y = (1.0 - 2.0 * film.y) * params.tanHalfFovY;
    origin = params.eye;
    dir = normalize(params.forward + x * params.right + y * params.up);
}

// Adds a finished sample's radiance to a pixel's running sum. A non-finite estimate (a pdf
// division gone wrong) counts as zero: the sample is still counted, so the sum stays an
// average over all samples. Kahan's step (shared/types.h, AccumSum): `precise` keeps the
// compiler from simplifying (t - sum) - y to 0, which would drop the compensation.
void addSample(inout AccumSum pixel, inout vec3 compensation, vec3 radiance) {
    if (!isFiniteVec(radiance)) radiance = vec3(0.0);
    precise vec3 y = radiance - compensation;
    precise vec3 t = pixel.sum + y;
    precise vec3 lost = (t - pixel.sum) - y;
    compensation = lost;
    pixel.sum = t;
    pixel.count += 1u;
}

// Adds the pass's samples of `pixel` (from firstSampleOf to sampleIndex + sampleCount) to
// its sums, in sample order and in a register, so that the sums are the same, bit for bit,
// as with one dispatch per sample, without a dispatch's fixed cost per sample (on lavapipe,
// waking and waiting for its worker threads). A kernel that defines
// PENUMBRA_KERNEL_SAMPLE_LOOP brings its own, with the same contract
// (integrators/direct.comp, where it traces rays of two samples together).
#ifdef PENUMBRA_KERNEL_SAMPLE_LOOP
void addPixelSamples(uvec2 pixel);
#else
// One pixel sample's radiance estimate, and what its camera ray found for the AOV layers
// (left a miss where kAovs is 0): each integrator kernel defines it.
vec3 pixelSample(uvec2 pixel, uint sampleIndex, out AovFirstHit aov);

void addPixelSamples(uvec2 pixel) {
    uint index = pixel.y * params.width + pixel.x;
    AccumSum sum = accum[index];
    vec3 compensation = accumCompensation[index].compensation;
    AovSums aovs = loadAovSums(index);
    uint end = pass.sampleIndex + pass.sampleCount;
    for (uint s = firstSampleOf(sum); s < end; ++s) {
        AovFirstHit first;
        vec3 radiance = pixelSample(pixel, s, first);
        // A sample whose loops were cut may be wrong: a later pass takes it up again.
        if (loopsWereCut()) break;
        addSample(sum, compensation, radiance);
        addAovSample(aovs, pixel, s, radiance, first);
    }
    accum[index] = sum;
    accumCompensation[index].compensation = compensation;
    storeAovSums(index, aovs);
}
#endif

// Which pixels an invocation renders (render/tile_queue.h). With the tile queue
// (pass.queueTiles > 0, on CPU devices with several worker threads) each invocation takes
// the next pixel from the counter until the band's pixels run out, so that a worker thread
// whose workgroups cost less, or that the operating system ran more, goes on with the rest
// instead of waiting: lavapipe hands each thread a fixed range of a dispatch's workgroups.
// A pixel's samples do not depend on who renders it, so the image is the same bit for bit.
// Without it, workgroup (x, y) renders tile (x, y) of the band, one pixel per invocation.
// When counting, the invocation then hands its ray tally to the counters. An invocation
// whose loops were cut short says so, for the host to render the samples it left
// (Renderer::renderAll; such drivers get no tile queue).
void main() {
    bool queue = pass.queueTiles > 0u;
    // At most 16384^2 pixels (the film's limit): the counter, which also counts each
    // invocation's last, empty-handed take, stays far from wrapping.
    uint pixels = queue ? pass.queueTiles * uint(TILE_PIXELS) : 1u;
    uint index = queue ? atomicAdd(nextQueuedPixel, 1u) : 0u;
    // One call of addPixelSamples for both ways, which the compiler inlines, so the kernel
    // holds the integrator once: two calls took the driver twice as long to compile it.
    while (index < pixels) {
        uvec2 local = queue ? queuedPixel(index) : gl_WorkGroupID.xy * uint(TILE_SIZE) + gl_LocalInvocationID.xy;
        uvec2 pixel;
        if (bandPixel(local, pixel)) addPixelSamples(pixel);
        index = queue ? atomicAdd(nextQueuedPixel, 1u) : pixels;
    }
    if (kCountRays != 0u) atomicAdd(rayCount, raysTraced);
    if (loopsWereCut()) atomicAdd(loopsCut, 1u);
}

#endif
