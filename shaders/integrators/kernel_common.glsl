// What every integrator kernel shares: the render parameters, the accumulation buffer,
// the per-pass constants, camera rays (box filter over the pixel) and the guarded
// accumulation that keeps NaN/Inf out of the sums.
#ifndef PENUMBRA_KERNEL_COMMON_GLSL
#define PENUMBRA_KERNEL_COMMON_GLSL

#include "shared/types.h"
#include "common/math.glsl"
#include "common/rng.glsl"
#include "geometry/ray_count.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = BINDING_PARAMS) uniform Params { RenderParams params; };
layout(std430, binding = BINDING_ACCUM) restrict buffer Accumulation { vec4 accum[]; };
layout(push_constant) uniform Pass { PassConstants pass; };
layout(std430, binding = BINDING_RAY_COUNT) restrict buffer RayCount { uint rayCount; };

#ifdef PENUMBRA_NODE_ADDRESS
// Where the "_address" kernels read the BVH's nodes from, and where this invocation keeps
// its traversal stack (geometry/bvh.glsl): entry i * stackDepth for invocation i of the
// dispatch (render/traversal_stacks.h keeps the dispatches within the buffer).
uvec2 bvhNodeAddress() { return uvec2(pass.nodeAddressLow, pass.nodeAddressHigh); }
uvec2 bvhStackAddress() { return uvec2(pass.stackAddressLow, pass.stackAddressHigh); }
uint bvhStackDepth() { return pass.stackDepth; }
uint bvhStackInvocation() {
    uvec3 size = gl_NumWorkGroups * gl_WorkGroupSize;
    return gl_GlobalInvocationID.x + size.x * (gl_GlobalInvocationID.y + size.y * gl_GlobalInvocationID.z);
}
#endif

// This invocation's pixel, or false when it lies outside the film / the pass's rows.
// The dispatch's z interleaves tile rows (render/tile_rows.h): slice z of Z holds the rows
// z, z + Z, z + 2Z, ..., so that each of a CPU device's threads, which take contiguous
// ranges of workgroups, gets rows from all over the film.
bool invocationPixel(out uvec2 pixel) {
    uint tileRow = gl_WorkGroupID.y * gl_NumWorkGroups.z + gl_WorkGroupID.z;
    uvec2 local = uvec2(gl_WorkGroupID.x, tileRow) * gl_WorkGroupSize.xy + gl_LocalInvocationID.xy;
    pixel = uvec2(local.x + pass.firstColumn, local.y + pass.firstRow);
    return pixel.x < params.width && local.y < pass.rowCount && pixel.y < params.height;
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

// One pixel sample's radiance estimate: each integrator kernel defines it.
vec3 pixelSample(uvec2 pixel, uint sampleIndex);

// Adds the pass's sampleCount samples of this invocation's pixel to its sums, in sample
// order and in a register, so that the sums are the same, bit for bit, as with one
// dispatch per sample, without a dispatch's fixed cost per sample (on lavapipe, waking
// and waiting for its worker threads). A non-finite estimate (a pdf division gone wrong)
// counts as zero: the sample is still counted, so the sum stays an average over all
// samples. When counting, it also hands this invocation's ray tally to the ray-count buffer.
void main() {
    uvec2 pixel;
    if (!invocationPixel(pixel)) return;
    uint index = pixel.y * params.width + pixel.x;
    vec4 sum = accum[index];
    for (uint k = 0u; k < pass.sampleCount; ++k) {
        vec3 radiance = pixelSample(pixel, pass.sampleIndex + k);
        if (!isFiniteVec(radiance)) radiance = vec3(0.0);
        sum += vec4(radiance, 1.0);
    }
    accum[index] = sum;
    if (kCountRays != 0u) atomicAdd(rayCount, raysTraced);
}

#endif
