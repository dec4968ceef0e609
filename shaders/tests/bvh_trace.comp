// Test entry point for geometry/bvh.glsl: one invocation per ray, writes the closest hit
// (t and primitive index in leaf order, NO_HIT if none) and the any-hit flag for the same
// ray and tMax. Used by tests/test_bvh.cpp, which compares against the CPU; its
// bvh_trace_inline<N> variants (cmake/EmbedShaders.cmake) test the inline primitives.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/types.h"
#include "geometry/bvh.glsl"

layout(local_size_x = 64) in;

struct TraceRay {
    vec4 originTMax;  // xyz origin, w tMax
    vec4 dir;         // xyz direction
};
struct TraceResult {
    float t;
    uint primitive;
    uint anyHit;
    uint pad;
};

layout(std430, binding = 0) readonly restrict buffer Rays { TraceRay rays[]; };
layout(std430, binding = 1) writeonly restrict buffer Results { TraceResult results[]; };
// The node buffer's and the traversal stacks' device addresses are read by the "_address"
// variant only: BVH_STACKS_PER_INVOCATION stacks of stackDepth entries per ray. The
// primitives beside the tree: besideFirst on. `pairs` (the "_address" variant only): the
// queries go through tracePair, as the render kernel traces them (main says which
// invocation traces which ray's any hit).
layout(push_constant) uniform Push {
    uint rayCount, nodeAddressLow, nodeAddressHigh, stackAddressLow, stackAddressHigh, stackDepth, besideFirst,
        besideCount, pairs;
};

uvec2 bvhBesideRange() { return uvec2(besideFirst, besideCount); }

#ifdef PENUMBRA_NODE_ADDRESS
uvec2 bvhNodeAddress() { return uvec2(nodeAddressLow, nodeAddressHigh); }
uvec2 bvhStackAddress() { return uvec2(stackAddressLow, stackAddressHigh); }
uint bvhStackDepth() { return stackDepth; }
uint bvhStackInvocation() { return gl_GlobalInvocationID.x; }
#endif

#ifdef PENUMBRA_NODE_ADDRESS
// Ray r as an any-hit query for tracePair.
AnyHitRay anyHitRay(uint r) {
    return AnyHitRay(rays[r].originTMax.xyz, rays[r].dir.xyz, rays[r].originTMax.w, true, uvec2(NO_HIT));
}
#endif

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= rayCount) return;
    vec3 origin = rays[i].originTMax.xyz;
    float tMax = rays[i].originTMax.w;
    vec3 dir = rays[i].dir.xyz;
#ifdef PENUMBRA_NODE_ADDRESS
    if (pairs != 0u) {
        // Invocation i traces ray i's closest hit, and in the any-hit slot rays 2i and 2i + 1
        // (where there are such rays): both (B, then C), only 2i as C (no B), or only 2i as
        // B (no C); a ray left out of the slot is traced alone with traceAny.
        uint b = 2u * i, c = 2u * i + 1u;
        bool tracedB = b < rayCount && i % 3u != 1u;
        bool tracedC = b < rayCount && i % 3u != 2u;
        uint rayB = b, rayC = i % 3u == 1u ? b : c;
        uint alone = i % 3u == 0u ? rayCount : c;
        AnyHitRay anyB = noAnyHitRay(), anyC = noAnyHitRay();
        if (tracedB) anyB = anyHitRay(rayB);
        if (tracedC && rayC < rayCount) anyC = anyHitRay(rayC);
        Hit closest;
        bool blockedB, blockedC;
        bool found = tracePair(origin, dir, tMax, true, uvec2(NO_HIT), closest, anyB, anyC, blockedB, blockedC);
        results[i].t = found ? closest.t : 0.0;
        results[i].primitive = found ? closest.primitive : NO_HIT;
        results[i].pad = 0u;
        if (anyB.traced) results[rayB].anyHit = blockedB ? 1u : 0u;
        if (anyC.traced) results[rayC].anyHit = blockedC ? 1u : 0u;
        if (b < rayCount && alone < rayCount) {
            AnyHitRay r = anyHitRay(alone);
            results[alone].anyHit = traceAny(r.origin, r.dir, r.tMax) ? 1u : 0u;
        }
        return;
    }
#endif
    Hit hit;
    bool found = traceClosest(origin, dir, tMax, hit);
    TraceResult result;
    result.t = found ? hit.t : 0.0;
    result.primitive = found ? hit.primitive : NO_HIT;
    result.anyHit = traceAny(origin, dir, tMax) ? 1u : 0u;
    result.pad = 0u;
    results[i] = result;
}
