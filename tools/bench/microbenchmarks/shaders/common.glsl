// Shared by the micro-benchmark kernels: the push constants, the result buffer, a hash for
// per-lane values (hash.h) and a ray-box slab test standing in for a traversal step's arithmetic.
#ifndef MICROBENCH_COMMON_GLSL
#define MICROBENCH_COMMON_GLSL

layout(local_size_x = 64) in;

// Steps per invocation (fetch and step kernels) or tree depth (stack kernels).
layout(constant_id = 0) const uint STEPS = 32u;

layout(push_constant) uniform Push {
    uvec2 address;     // buffer device address of the node table (SOURCE_BDA, step kernels)
    uint mask;         // node count - 1 (node count is a power of two)
    uint threshold;    // stack kernels: a child is visited when a 16-bit hash is below it;
                       // STEP_RAYS_NO_FRAME: every node's meta word
    vec4 boxOrigin;    // packed nodes: box = boxOrigin + boxScale * quantized / 255;
                       // STEP_RAYS_NO_FRAME: every node's origin (xyz)
    vec4 boxScale;
} pc;

// One result per invocation, written once at the end: keeps the loop from being optimised
// away and lets the driver check that every variant computed the same thing.
layout(std430, binding = 0) writeonly restrict buffer Results { vec2 results[]; };

#include "hash.h"

// Slab test (Kay and Kajiya 1986) of the invocation's ray against [lo, hi]: the entry
// distance when hit, else 0. Branch-free, as in shaders/geometry/intersect.glsl.
float slab(vec3 lo, vec3 hi, vec3 origin, vec3 invDir) {
    vec3 t0 = (lo - origin) * invDir;
    vec3 t1 = (hi - origin) * invDir;
    vec3 tn = min(t0, t1), tf = max(t0, t1);
    float tEnter = max(max(tn.x, tn.y), max(tn.z, 0.0));
    float tExit = min(min(tf.x, tf.y), tf.z);
    return tEnter <= tExit ? tEnter : 0.0;
}

#endif
