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
// queries go through tracePair, as the render kernel traces them, invocation i tracing ray
// i's closest hit together with ray rayCount - 1 - i's any hit.
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

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= rayCount) return;
    vec3 origin = rays[i].originTMax.xyz;
    float tMax = rays[i].originTMax.w;
    vec3 dir = rays[i].dir.xyz;
#ifdef PENUMBRA_NODE_ADDRESS
    if (pairs != 0u) {
        uint j = rayCount - 1u - i;
        Hit closest;
        bool blocked;
        bool found = tracePair(origin, dir, tMax, true, uvec2(NO_HIT), closest, rays[j].originTMax.xyz, rays[j].dir.xyz,
                               rays[j].originTMax.w, true, uvec2(NO_HIT), blocked);
        results[i].t = found ? closest.t : 0.0;
        results[i].primitive = found ? closest.primitive : NO_HIT;
        results[i].pad = 0u;
        results[j].anyHit = blocked ? 1u : 0u;
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
