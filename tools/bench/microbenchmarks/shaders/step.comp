#version 460
// Cost of one traversal step in two mappings of the work onto SIMD lanes. Every ray walks
// STEPS nodes of a table through the table's device address: at each node it tests the
// node's quantized child boxes (decoded as shaders/geometry/bvh.glsl decodes them), goes on
// to the nearest child hit (to a child chosen by the step number when none is hit), and the
// child's reference, XOR a per-ray salt, names the next node, so that the lanes' nodes
// differ and no load can be hoisted. The stack is left out of both.
// - STEP_RAYS: one ray per invocation and four-wide nodes, as the renderer traces today
//   (shared/types.h WideNode: 64 bytes).
// - STEP_RAYS_FLOAT: that step on the same boxes stored as floats, 128 bytes a node (the
//   planes of each axis and side for the four children, the references, the child mask):
//   no decode, twice the bytes.
// - STEP_RAYS_NO_FRAME: that step without loading the node's frame (base, exponents,
//   child mask: two of its seven 64-bit words), which the push constants give instead (every
//   node of the table has the same): what a node whose frame came from its parent, and not
//   from memory, would save at most.
// - STEP_RAYS_PAIR: that step for two rays per invocation, interleaved: how much of a
//   step is waiting on its loads, which a second independent ray lets the CPU overlap.
// - STEP_RAYS_QUAD: that step for four rays per invocation, interleaved: whether more
//   chains than two still overlap (or spill the registers they need).
// - STEP_RAYS_PREFETCH: that step, which also loads the first word of each of the four
//   nodes it could go on to as soon as it has the node's references, so that the next
//   step's line is on its way while the boxes are tested (a load used only by a test that
//   never passes, since GLSL has no prefetch).
// - STEP_CHILDREN8: one ray per eight invocations and eight-wide nodes, one child per
//   invocation; the nearest child is found with subgroup shuffles. A node is 96 bytes: a
//   frame (origin, per-axis step exponents, child mask), the children's base index, then
//   eight 8-byte child records (six plane bytes, a 16-bit offset from the base).
// - STEP_CHILDREN8_ALONE: that step without the shuffles: each lane goes on to its own
//   child, hit or not, so the lanes part ways after the first node. Not a traversal: what
//   the rest of the eight-wide step costs, the floor under any way of combining the lanes.
// Compiled once per variant by tools/bench/microbenchmarks/CMakeLists.txt (-DSTEP_*).
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#if defined(STEP_CHILDREN8_ALONE)
#define STEP_CHILDREN8  // the same step with its lanes' results not combined (below)
#endif
#if defined(STEP_RAYS_FLOAT) || defined(STEP_RAYS_NO_FRAME) || defined(STEP_RAYS_PAIR) || defined(STEP_RAYS_QUAD) || \
    defined(STEP_RAYS_PREFETCH)
#define STEP_RAYS  // variants of the same step (below)
#endif
#if defined(STEP_CHILDREN8)
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#endif
#include "common.glsl"
#include "common/math.glsl"  // FLOAT_MAX
#include "shared/types.h"     // the renderer's WideNode layout, BOX_EXIT_SCALE
#include "geometry/wide_node.glsl"  // its planes' decode

layout(buffer_reference, std430, buffer_reference_align = 8) readonly restrict buffer Words64 { uint64_t v[]; };

// An origin in [0, 1)^3 and an inverse direction in [-8, 8], never 0, from exact
// operations only, so that the program can replay the walk on the CPU bit for bit.
void makeRay(uint salt, out vec3 origin, out vec3 invDir) {
    origin = vec3((uvec3(salt) >> uvec3(0u, 8u, 16u)) & 255u) * (1.0 / 256.0);
    invDir = (vec3(uvec3(hash(salt), hash(salt + 1u), hash(salt + 2u)) & 1023u) - 511.5) * (1.0 / 64.0);
}

// 2^(e - 127) for the biased exponents in bytes 0-2 of `meta`.
vec3 stepOf(uint meta) { return uintBitsToFloat(((uvec3(meta) >> uvec3(0u, 8u, 16u)) & 0xffu) << 23u); }

#if defined(STEP_RAYS)

// Four floats from two 64-bit words.
vec4 planesAt(Words64 at, uint word) {
    return uintBitsToFloat(uvec4(unpackUint2x32(at.v[word]), unpackUint2x32(at.v[word + 1u])));
}

vec4 maxOfNumbers(vec4 a, vec4 b) { return mix(b, a, greaterThan(a, b)); }
vec4 minOfNumbers(vec4 a, vec4 b) { return mix(b, a, lessThan(a, b)); }

// Step s of the ray (salt, origin, invDir) at `node`: adds to `acc`, returns the next node.
uint wideStep(Words64 at, uint node, uint s, uint salt, vec3 origin, vec3 invDir, inout float acc) {
    bvec3 negative = lessThan(invDir, vec3(0.0));
    {
        // intersectWideNode (geometry/bvh.glsl), with tMax = FLOAT_MAX.
#if defined(STEP_RAYS_FLOAT)
        // Each side of each axis is two 64-bit words (four floats); the direction picks which.
        uint base = 16u * node;
        uvec3 nearAt = base + uvec3(0u, 2u, 4u) + mix(uvec3(0u), uvec3(6u), negative);
        uvec3 farAt = base + uvec3(0u, 2u, 4u) + mix(uvec3(6u), uvec3(0u), negative);
        vec4 nearX = (planesAt(at, nearAt.x) - origin.x) * invDir.x;
        vec4 nearY = (planesAt(at, nearAt.y) - origin.y) * invDir.y;
        vec4 nearZ = (planesAt(at, nearAt.z) - origin.z) * invDir.z;
        vec4 farX = (planesAt(at, farAt.x) - origin.x) * invDir.x;
        vec4 farY = (planesAt(at, farAt.y) - origin.y) * invDir.y;
        vec4 farZ = (planesAt(at, farAt.z) - origin.z) * invDir.z;
        uvec4 ref = uvec4(unpackUint2x32(at.v[base + 12u]), unpackUint2x32(at.v[base + 13u]));
        uint meta = unpackUint2x32(at.v[base + 14u]).x;
#else
#if defined(STEP_RAYS_NO_FRAME)
        uvec2 w0 = floatBitsToUint(pc.boxOrigin.xy), w1 = uvec2(floatBitsToUint(pc.boxOrigin.z), pc.threshold);
#else
        uvec2 w0 = unpackUint2x32(at.v[8u * node]), w1 = unpackUint2x32(at.v[8u * node + 1u]);
#endif
        uvec2 w2 = unpackUint2x32(at.v[8u * node + 2u]), w3 = unpackUint2x32(at.v[8u * node + 3u]);
        uvec2 w4 = unpackUint2x32(at.v[8u * node + 4u]), w5 = unpackUint2x32(at.v[8u * node + 5u]);
        uvec2 w6 = unpackUint2x32(at.v[8u * node + 6u]);
        uvec4 frame = uvec4(w0, w1), planesA = uvec4(w2, w3), planesB = uvec4(w4, w5);
        uvec4 ref = uvec4(planesB.zw, w6);
#if defined(STEP_RAYS_PREFETCH)
        uvec4 ahead = (ref ^ salt) & pc.mask;
        uint64_t touched = at.v[8u * ahead.x] ^ at.v[8u * ahead.y] ^ at.v[8u * ahead.z] ^ at.v[8u * ahead.w];
        if (touched == 0xffffffffffffffffUL && pc.threshold == 1u) acc += 1.0;  // never: the table has no such word
#endif
        // Decoded as geometry/bvh.glsl decodes them (wide_node.glsl).
        vec3 base = uintBitsToFloat(frame.xyz);
        uvec3 exponentBits = ((uvec3(frame.w) >> uvec3(0u, 8u, 16u)) & 0xffu) << 23u;
        uvec3 nearWords = mix(uvec3(planesA.xyz), uvec3(planesA.w, planesB.xy), negative);
        uvec3 farWords = mix(uvec3(planesA.w, planesB.xy), uvec3(planesA.xyz), negative);
        vec4 nearX = wideChildPlaneDistances(nearWords.x, base.x, exponentBits.x, origin.x, invDir.x);
        vec4 nearY = wideChildPlaneDistances(nearWords.y, base.y, exponentBits.y, origin.y, invDir.y);
        vec4 nearZ = wideChildPlaneDistances(nearWords.z, base.z, exponentBits.z, origin.z, invDir.z);
        vec4 farX = wideChildPlaneDistances(farWords.x, base.x, exponentBits.x, origin.x, invDir.x);
        vec4 farY = wideChildPlaneDistances(farWords.y, base.y, exponentBits.y, origin.y, invDir.y);
        vec4 farZ = wideChildPlaneDistances(farWords.z, base.z, exponentBits.z, origin.z, invDir.z);
        uint meta = frame.w;
#endif
        vec4 tNear = maxOfNumbers(maxOfNumbers(nearX, nearY), maxOfNumbers(nearZ, vec4(0.0)));
        vec4 tFar = minOfNumbers(minOfNumbers(farX, farY), minOfNumbers(farZ, vec4(FLOAT_MAX))) * BOX_EXIT_SCALE;
        bvec4 hit = lessThanEqual(tNear, tFar);
        uint hits = (meta >> WIDE_CHILD_MASK_SHIFT) & ((hit.x ? 1u : 0u) | (hit.y ? 2u : 0u) | (hit.z ? 4u : 0u) | (hit.w ? 8u : 0u));
        // nearestChild (geometry/bvh.glsl).
        uint c = s & 3u;
        float best = 0.0;
        bool found = false;
        for (uint k = 0u; k < 4u; ++k) {
            if ((hits & (1u << k)) != 0u && (!found || tNear[k] < best)) {
                c = k;
                best = tNear[k];
                found = true;
            }
        }
        uint next = c == 0u ? ref.x : (c == 1u ? ref.y : (c == 2u ? ref.z : ref.w));
        acc += best + float(bitCount(hits));
        return (next ^ salt) & pc.mask;
    }
}

void main() {
    Words64 at = Words64(pc.address);
#if defined(STEP_RAYS_PAIR)
    // Two rays per invocation, a step of each per iteration: two independent chains of
    // loads for the CPU to overlap. The result holds the first ray's sum, the second's node.
    uint saltA = hash(2u * gl_GlobalInvocationID.x), saltB = hash(2u * gl_GlobalInvocationID.x + 1u);
    vec3 originA, invDirA, originB, invDirB;
    makeRay(saltA, originA, invDirA);
    makeRay(saltB, originB, invDirB);
    uint nodeA = saltA & pc.mask, nodeB = saltB & pc.mask;
    float accA = 0.0, accB = 0.0;
    for (uint s = 0u; s < STEPS; ++s) {
        nodeA = wideStep(at, nodeA, s, saltA, originA, invDirA, accA);
        nodeB = wideStep(at, nodeB, s, saltB, originB, invDirB, accB);
    }
    results[gl_GlobalInvocationID.x] = vec2(accA, float(nodeB));
#elif defined(STEP_RAYS_QUAD)
    // Four rays per invocation, likewise: ray 4i's sum, ray 4i + 3's node.
    uint salt0 = hash(4u * gl_GlobalInvocationID.x), salt1 = hash(4u * gl_GlobalInvocationID.x + 1u);
    uint salt2 = hash(4u * gl_GlobalInvocationID.x + 2u), salt3 = hash(4u * gl_GlobalInvocationID.x + 3u);
    vec3 origin0, invDir0, origin1, invDir1, origin2, invDir2, origin3, invDir3;
    makeRay(salt0, origin0, invDir0);
    makeRay(salt1, origin1, invDir1);
    makeRay(salt2, origin2, invDir2);
    makeRay(salt3, origin3, invDir3);
    uint node0 = salt0 & pc.mask, node1 = salt1 & pc.mask, node2 = salt2 & pc.mask, node3 = salt3 & pc.mask;
    float acc0 = 0.0, acc1 = 0.0, acc2 = 0.0, acc3 = 0.0;
    for (uint s = 0u; s < STEPS; ++s) {
        node0 = wideStep(at, node0, s, salt0, origin0, invDir0, acc0);
        node1 = wideStep(at, node1, s, salt1, origin1, invDir1, acc1);
        node2 = wideStep(at, node2, s, salt2, origin2, invDir2, acc2);
        node3 = wideStep(at, node3, s, salt3, origin3, invDir3, acc3);
    }
    results[gl_GlobalInvocationID.x] = vec2(acc0, float(node3));
    // Rays 1 and 2 kept live by a store that never happens (a node index is masked by
    // pc.mask, never all ones), which the compiler cannot know.
    if (node1 == 0xffffffffu && node2 == 0xffffffffu) results[gl_GlobalInvocationID.x] = vec2(acc1, acc2);
#else
    uint id = gl_GlobalInvocationID.x;
    uint salt = hash(id);
    vec3 origin, invDir;
    makeRay(salt, origin, invDir);
    uint node = salt & pc.mask;
    float acc = 0.0;
    for (uint s = 0u; s < STEPS; ++s) node = wideStep(at, node, s, salt, origin, invDir, acc);
    results[id] = vec2(acc, float(node));
#endif
}

#elif defined(STEP_CHILDREN8)

// The lane of the group of eight that holds `lane`'s ray.
uint groupLane(uint lane) { return (gl_SubgroupInvocationID & ~7u) | lane; }

void main() {
    uint child = gl_GlobalInvocationID.x & 7u;  // subgroups are eight lanes or a multiple
    uint salt = hash(gl_GlobalInvocationID.x >> 3u);
    vec3 origin, invDir;
    makeRay(salt, origin, invDir);
    bvec3 negative = lessThan(invDir, vec3(0.0));
    uint node = salt & pc.mask;
    float acc = 0.0;
    Words64 at = Words64(pc.address);
    for (uint s = 0u; s < STEPS; ++s) {
        uvec2 w0 = unpackUint2x32(at.v[12u * node]), w1 = unpackUint2x32(at.v[12u * node + 1u]);
        uint base = unpackUint2x32(at.v[12u * node + 2u]).x;
        uvec2 record = unpackUint2x32(at.v[12u * node + 4u + child]);
        vec3 corner = uintBitsToFloat(uvec3(w0, w1.x));
        vec3 step = stepOf(w1.y);
        vec3 lo = corner + vec3((uvec3(record.x) >> uvec3(0u, 8u, 16u)) & 0xffu) * step;
        vec3 hi = corner + vec3(record.x >> 24u, record.y & 0xffu, (record.y >> 8u) & 0xffu) * step;
        vec3 tn = (mix(lo, hi, negative) - origin) * invDir;
        vec3 tf = (mix(hi, lo, negative) - origin) * invDir;
        float tNear = max(max(tn.x, tn.y), max(tn.z, 0.0));
        float tFar = min(min(tf.x, tf.y), min(tf.z, FLOAT_MAX)) * BOX_EXIT_SCALE;
        bool hit = ((w1.y >> (WIDE_CHILD_MASK_SHIFT + child)) & 1u) != 0u && tNear <= tFar;
#if defined(STEP_CHILDREN8_ALONE)
        acc += hit ? tNear : 0.0;
        node = ((base + (record.y >> 16u)) ^ salt) & pc.mask;
        continue;
#endif
        // The nearest child hit, lowest lane on ties: a butterfly over the eight lanes of
        // (entry distance's bits, lane). Entry distances are >= 0, so their bits order as
        // the floats do; a miss is all ones.
        uint key = hit ? floatBitsToUint(tNear) : 0xffffffffu, best = child;
        uint hits = hit ? 1u << child : 0u;
        for (uint m = 1u; m < 8u; m <<= 1u) {
            uint otherKey = subgroupShuffleXor(key, m), otherLane = subgroupShuffleXor(best, m);
            bool take = otherKey < key || (otherKey == key && otherLane < best);
            key = take ? otherKey : key;
            best = take ? otherLane : best;
            hits |= subgroupShuffleXor(hits, m);
        }
        uint chosen = hits == 0u ? (s & 7u) : best;
        uint next = base + subgroupShuffle(record.y >> 16u, groupLane(chosen));
        acc += (hits == 0u ? 0.0 : uintBitsToFloat(key)) + float(bitCount(hits));
        node = (next ^ salt) & pc.mask;
    }
    results[gl_GlobalInvocationID.x] = vec2(acc, float(node));
}

#else
#error "no STEP_* defined"
#endif
