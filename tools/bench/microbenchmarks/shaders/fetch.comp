#version 460
// Cost of fetching one BVH-like node inside a divergent loop: every invocation walks
// STEPS nodes of a table, the next index read from the node just loaded (so no load can be
// hoisted and the lanes' indices differ), with a ray-box test on each node's box.
// Compiled once per node source by tools/bench/microbenchmarks/CMakeLists.txt (-DSOURCE_*).
#extension GL_EXT_buffer_reference : enable
#extension GL_EXT_buffer_reference_uvec2 : enable
#extension GL_GOOGLE_include_directive : require
#if defined(SOURCE_SSBO64) || defined(SOURCE_BDA64)
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#endif
#include "common.glsl"

// Small tables (UBO, shared memory) hold SMALL_NODES nodes of 32 bytes: 32 KiB, the most
// workgroup memory lavapipe offers (maxComputeSharedMemorySize).
#define SMALL_NODES 1024

// ---- Where a 32-byte node (two vec4: min.xyz + next, max.xyz + 0) comes from -----------
#if defined(SOURCE_SSBO)
layout(std430, binding = 1) readonly restrict buffer Nodes { vec4 nodes[]; };
#define LOAD(i) nodes[i]
#elif defined(SOURCE_UBO)
layout(std140, binding = 1) uniform Nodes { vec4 nodes[2 * SMALL_NODES]; };
#define LOAD(i) nodes[i]
#elif defined(SOURCE_TEXEL)
layout(binding = 1) uniform samplerBuffer nodes;  // RGBA32F
#define LOAD(i) texelFetch(nodes, int(i))
#elif defined(SOURCE_IMAGE)
layout(binding = 1, rgba32f) uniform readonly restrict imageBuffer nodes;
#define LOAD(i) imageLoad(nodes, int(i))
#elif defined(SOURCE_SHARED)
layout(std430, binding = 1) readonly restrict buffer Nodes { vec4 nodes[]; };
shared vec4 sharedNodes[2 * SMALL_NODES];
#define LOAD(i) sharedNodes[i]
#elif defined(SOURCE_BDA)
layout(buffer_reference, std430, buffer_reference_align = 16) readonly restrict buffer NodeRef { vec4 v[]; };
#define LOAD(i) NodeRef(pc.address).v[i]
// ---- The same 32-byte node in one 64-bit-word load (u64vec4), as the renderer reads -----
#elif defined(SOURCE_SSBO64)
layout(std430, binding = 1) readonly restrict buffer Nodes { u64vec4 nodes[]; };
#define LOAD64(i) nodes[i]
#elif defined(SOURCE_BDA64)
layout(buffer_reference, std430, buffer_reference_align = 32) readonly restrict buffer NodeRef { u64vec4 v[]; };
#define LOAD64(i) NodeRef(pc.address).v[i]
// ---- 16-byte nodes (uvec4): x = next index, y = min.xyz, max.x as unorm8, z = max.yz ---
#elif defined(SOURCE_PACKED16_SSBO)
layout(std430, binding = 1) readonly restrict buffer Nodes { uvec4 nodes[]; };
#define LOADQ(i) nodes[i]
#elif defined(SOURCE_PACKED16_UBO)
layout(std140, binding = 1) uniform Nodes { uvec4 nodes[SMALL_NODES]; };
#define LOADQ(i) nodes[i]
#elif defined(SOURCE_PACKED16_TEXEL)
layout(binding = 1) uniform usamplerBuffer nodes;  // RGBA32UI
#define LOADQ(i) texelFetch(nodes, int(i))
// ---- 8-byte nodes (uvec2): x = next index, y = six 5-bit planes -------------------------
#elif defined(SOURCE_PACKED8_SSBO)
layout(std430, binding = 1) readonly restrict buffer Nodes { uvec2 nodes[]; };
#define LOAD8(i) nodes[i]
#elif defined(SOURCE_PACKED8_TEXEL)
layout(binding = 1) uniform usamplerBuffer nodes;  // RG32UI
#define LOAD8(i) texelFetch(nodes, int(i)).xy
#else
#error "no SOURCE_* defined"
#endif

void main() {
    uint id = gl_GlobalInvocationID.x;
#if defined(SOURCE_SHARED)
    // Copied in once per workgroup, as a renderer would before its traversal.
    for (uint k = gl_LocalInvocationIndex; k < 2u * SMALL_NODES; k += gl_WorkGroupSize.x) sharedNodes[k] = nodes[k];
    barrier();
#endif
    uint salt = hash(id);
    uint index = salt & pc.mask;
    vec3 origin = vec3(float(salt & 255u), float((salt >> 8) & 255u), float((salt >> 16) & 255u)) / 255.0;
    vec3 invDir = 1.0 / (vec3(hash(salt) & 1023u, hash(salt + 1u) & 1023u, hash(salt + 2u) & 1023u) / 1023.0 - 0.5 + 1e-3);
    float acc = 0.0;
    for (uint step = 0u; step < STEPS; ++step) {
#if defined(LOAD64)
        u64vec4 w = LOAD64(index);
        vec4 a = vec4(uintBitsToFloat(unpackUint2x32(w.x)), uintBitsToFloat(unpackUint2x32(w.y)));
        vec4 b = vec4(uintBitsToFloat(unpackUint2x32(w.z)), uintBitsToFloat(unpackUint2x32(w.w)));
        vec3 lo = a.xyz, hi = b.xyz;
        uint next = uint(a.w);
#elif defined(LOAD)
        vec4 a = LOAD(2u * index);
        vec4 b = LOAD(2u * index + 1u);
        vec3 lo = a.xyz, hi = b.xyz;
        uint next = uint(a.w);
#elif defined(LOADQ)
        uvec4 q = LOADQ(index);
        vec4 q0 = unpackUnorm4x8(q.y), q1 = unpackUnorm4x8(q.z);
        vec3 lo = pc.boxOrigin.xyz + pc.boxScale.xyz * q0.xyz;
        vec3 hi = pc.boxOrigin.xyz + pc.boxScale.xyz * vec3(q0.w, q1.xy);
        uint next = q.x;
#else
        uvec2 q = LOAD8(index);
        vec3 lo = pc.boxOrigin.xyz + pc.boxScale.xyz / 31.0 *
                  vec3(bitfieldExtract(q.y, 0, 5), bitfieldExtract(q.y, 5, 5), bitfieldExtract(q.y, 10, 5));
        vec3 hi = pc.boxOrigin.xyz + pc.boxScale.xyz / 31.0 *
                  vec3(bitfieldExtract(q.y, 15, 5), bitfieldExtract(q.y, 20, 5), bitfieldExtract(q.y, 25, 5));
        uint next = q.x;
#endif
        acc += slab(lo, hi, origin, invDir);
        index = (next ^ salt) & pc.mask;
    }
    results[id] = vec2(acc, float(index));
}
