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
// variant only: stackDepth entries per ray. The primitives beside the tree: besideFirst on.
layout(push_constant) uniform Push {
    uint rayCount, nodeAddressLow, nodeAddressHigh, stackAddressLow, stackAddressHigh, stackDepth, besideFirst,
        besideCount;
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
    Hit hit;
    bool found = traceClosest(origin, dir, tMax, hit);
    TraceResult result;
    result.t = found ? hit.t : 0.0;
    result.primitive = found ? hit.primitive : NO_HIT;
    result.anyHit = traceAny(origin, dir, tMax) ? 1u : 0u;
    result.pad = 0u;
    results[i] = result;
}
