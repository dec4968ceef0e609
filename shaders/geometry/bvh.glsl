// Traversal of the flat BVH built by host/bvh/build.cpp: closest hit for camera and
// bounce rays, any hit for shadow rays. Declares the node and primitive buffers; what a hit
// means for shading (position, normals, material) is in surface.glsl.
// host/bvh/traverse.cpp mirrors both queries for the CPU tests.
#ifndef PENUMBRA_BVH_GLSL
#define PENUMBRA_BVH_GLSL

#include "shared/types.h"
#include "common/math.glsl"
#include "common/specialization.glsl"
#include "geometry/intersect.glsl"
#include "geometry/wide_node.glsl"
#include "geometry/ray_count.glsl"

// The tree in four-wide nodes with quantized child boxes (shared/types.h, WideNode). The
// traversal reads primitives through a texel buffer (texelFetch on a usamplerBuffer), and
// nodes through a texel buffer, a storage buffer or that buffer's device address, as the
// specialization constant kNodeReads says: llvmpipe 22.3 turns a storage-buffer load inside a loop into a loop over
// the SIMD lanes with a bounds-check branch per component, a texel fetch into a branch-free
// gather of four words (docs/performance-history/round-02.md); 25.0
// still loops over the lanes for the storage buffer, but a texel fetch has become an
// indirect call to a function of the descriptor's, and on the BVH's nodes the loop is the
// faster of the two (docs/performance-history/round-10.md). host/render/node_reads.h picks per driver.
layout(binding = BINDING_NODES) uniform usamplerBuffer nodeTexels;
// The "_int64" kernels view the storage buffer in 32-byte words: a node is two loads, and on
// lavapipe 25.0 each load is a loop over the SIMD lanes, so halving the loads measured
// 1.07-1.10x (docs/performance-history/round-11.md); the module then needs 64-bit integers (shaderInt64).
#ifdef PENUMBRA_INT64_LOADS
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
layout(std430, binding = BINDING_NODE_WORDS) readonly restrict buffer NodeQuads { u64vec4 nodeQuads[]; };
#ifdef PENUMBRA_NODE_ADDRESS
// The "_address" kernels make the same loads through the buffer's device address. On
// lavapipe 25.0 a load from a device address is a hardware gather, without the storage
// buffer's loop over the SIMD lanes and bounds check per component: the seven 64-bit words
// a node step uses are 14 vpgatherqq of four lanes each. 1.06-1.17x (docs/performance-history/round-12.md). Nothing
// checks the index, which the tree's own child references give and the traversal tests
// compare with the CPU's. The kernel defines bvhNodeAddress() (kernel_common.glsl: from
// PassConstants).
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
layout(buffer_reference, std430, buffer_reference_align = 32) readonly restrict buffer NodeQuadsAt { u64vec4 quads[]; };
uvec2 bvhNodeAddress();
// They also keep the traversal stack in memory through a device address, not in a local
// array: on lavapipe 25.0 a store to a local array at a per-lane index is a loop over the
// SIMD lanes with a branch on each lane's mask bit, which mispredicts as the lanes push at
// random; a store through an address is one masked scatter (vpscatterqd), a load one
// gather. 1.12-1.17x on scenes of 30k-1M primitives (docs/performance-history/round-13.md). The kernel defines the
// buffer's address, the entries per invocation and which invocation this is
// (kernel_common.glsl: from PassConstants and the dispatch; render/traversal_stacks.h sizes
// the buffer: childStackDepth entries, one per child still to visit, see traverse). An index
// past the last entry is clamped to it, so that a tree deeper than the host counted could
// only change the image, never write outside the buffer
// (Bvh.StackDepthIsTheLongestPathsInteriorNodes checks the count).
layout(buffer_reference, std430, buffer_reference_align = 4) restrict buffer TraversalStackAt { uint entries[]; };
uvec2 bvhStackAddress();
uint bvhStackDepth();
uint bvhStackInvocation();

// Stack `which` (< BVH_STACKS_PER_INVOCATION) of this invocation: bvhStackDepth() entries from
// entry (bvhStackInvocation() * BVH_STACKS_PER_INVOCATION + which) * bvhStackDepth(). A
// single traversal uses stack 0, tracePair stacks 0 and 1.
TraversalStackAt invocationStack(uint which) {
    uvec2 base = bvhStackAddress();
    uint carry;
    uint entry = (bvhStackInvocation() * BVH_STACKS_PER_INVOCATION + which) * bvhStackDepth();
    uint low = uaddCarry(base.x, entry * 4u, carry);
    return TraversalStackAt(uvec2(low, base.y + carry));
}
#endif
#else
layout(std430, binding = BINDING_NODE_WORDS) readonly restrict buffer NodeWords { uvec4 nodeWords[]; };
#endif
layout(binding = BINDING_PRIMITIVE_TEXELS) uniform usamplerBuffer primitiveTexels;
// Primitives in leaf order: Hit.primitive indexes this array. The render kernels read them
// through primitiveTexels only (loadPrimitive: traversal, shading, light sampling); the
// storage-buffer view is for the traversal test kernels (shaders/tests).
layout(std430, binding = BINDING_PRIMITIVES) readonly restrict buffer Primitives { Primitive primitives[]; };

Primitive loadPrimitive(uint index) {
    uvec4 a = texelFetch(primitiveTexels, int(PRIMITIVE_TEXELS * index));
    uvec4 b = texelFetch(primitiveTexels, int(PRIMITIVE_TEXELS * index + 1u));
    uvec4 c = texelFetch(primitiveTexels, int(PRIMITIVE_TEXELS * index + 2u));
    return Primitive(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w, uintBitsToFloat(c.xyz), c.w);
}

// The primitives beside the tree (host/bvh/bvh.h, Bvh::besideCount), first and count: every
// query tests them before it walks the tree. The kernel defines this (kernel_common.glsl:
// from RenderParams; the test kernels from their push constants).
uvec2 bvhBesideRange();

struct Hit {
    float t;           // ray parameter of the hit, in (0, tMax)
    uint primitive;    // index into primitives[], NO_HIT when nothing was hit
    vec2 uv;           // triangle: barycentrics of p1, p2; quad: (s, t); sphere: unused
    uint instance;     // the instance whose group's primitive it is (geometry/instances.glsl), else NO_HIT
};

// Only the kernels built with PENUMBRA_INLINE_GEOMETRY carry the inline tests: the
// "<kernel>_inline<N>" variants that cmake/EmbedShaders.cmake compiles (it says why).
#ifdef PENUMBRA_INLINE_GEOMETRY
#include "geometry/inline_geometry.glsl"
#endif

// The traversal is "while-while" (Aila & Laine 2009, "Understanding the Efficiency of Ray
// Traversal on GPUs"): an inner loop descends through interior nodes until this ray reaches
// a leaf, and only then are the leaf's primitives tested. llvmpipe runs eight rays in SIMD
// lanes and executes every branch under a mask, so a single loop with an "interior or
// leaf" branch pays for box tests and a primitive test in every iteration of every lane;
// here the lanes do their box tests together and their primitive tests together (what it
// bought: docs/performance-history/round-01.md).

// max and min of operands that are never NaN, as a comparison and a select: GLSL's max and
// min must return the other operand of a NaN, which llvmpipe does with two more
// instructions after each x86 maxps/minps. The slab distances below are never NaN: the
// ray's origin is finite, rayInverseDirection keeps 1 / dir finite and nonzero, and a
// decoded plane is finite or, where a node's step is 2^127, +inf, so (plane - origin) / dir
// is finite or infinite. (A NaN tMax, which no caller passes, makes every box miss.)
vec4 maxOfNumbers(vec4 a, vec4 b) { return mix(b, a, greaterThan(a, b)); }
vec4 minOfNumbers(vec4 a, vec4 b) { return mix(b, a, lessThan(a, b)); }

// The four children of wide node `node` tested against the ray: bit c of the result is set
// where child c exists and its box is hit before tMax, with entry distance tEntry[c] and
// destination ref[c] (offset | primCount << BVH_COUNT_SHIFT). The boxes are decoded from
// their bytes (shared/types.h: base + plane(E, q)) and tested with intersectBox's formula,
// four at a time; host/bvh/traverse.cpp decodes and tests them one by one, with the same
// operations. The "_address" kernels pass the nodes' buffer as `at`, read once a traversal.
#ifdef PENUMBRA_NODE_ADDRESS
uint intersectWideNode(NodeQuadsAt at, uint node, vec3 origin, vec3 invDir, float tMax, out vec4 tEntry, out uvec4 ref) {
#else
uint intersectWideNode(uint node, vec3 origin, vec3 invDir, float tMax, out vec4 tEntry, out uvec4 ref) {
#endif
    uvec4 frame, planesA, planesB, refsB;  // base, meta; loX, loY, loZ, hiX; hiY, hiZ, child 0, 1; child 2, 3
    uint word = WIDE_NODE_TEXELS * node;
    if (kNodeReads != NODE_READS_TEXELS) {
#ifdef PENUMBRA_INT64_LOADS
        // Each 64-bit word holds two of the node's 32-bit words, the first in its low half
        // (Vulkan devices store little endian; the traversal tests would see otherwise).
#ifdef PENUMBRA_NODE_ADDRESS
        u64vec4 low = at.quads[2u * node], high = at.quads[2u * node + 1u];
#else
        u64vec4 low = nodeQuads[2u * node], high = nodeQuads[2u * node + 1u];
#endif
        frame = uvec4(unpackUint2x32(low.x), unpackUint2x32(low.y));
        planesA = uvec4(unpackUint2x32(low.z), unpackUint2x32(low.w));
        planesB = uvec4(unpackUint2x32(high.x), unpackUint2x32(high.y));
        refsB = uvec4(unpackUint2x32(high.z), unpackUint2x32(high.w));
#else
        frame = nodeWords[word];
        planesA = nodeWords[word + 1u];
        planesB = nodeWords[word + 2u];
        refsB = nodeWords[word + 3u];
#endif
    } else {
        frame = texelFetch(nodeTexels, int(word));
        planesA = texelFetch(nodeTexels, int(word + 1u));
        planesB = texelFetch(nodeTexels, int(word + 2u));
        refsB = texelFetch(nodeTexels, int(word + 3u));
    }
    ref = uvec4(planesB.zw, refsB.xy);
    // Planes built from their bits (wide_node.glsl) save a conversion and a multiply per
    // plane against corner + float(q) * step: a step of the "_address" kernels on lavapipe
    // 25.0 takes 383 instructions instead of 410, 1.01-1.04x on 30k-1M triangles
    // (docs/performance-history/round-19.md).
    vec3 base = uintBitsToFloat(frame.xyz);
    uvec3 exponentBits = ((uvec3(frame.w) >> uvec3(0u, 8u, 16u)) & 0xffu) << 23u;
    // intersectBox (intersect.glsl) for the four boxes: the near planes chosen by the sign
    // of the direction (here the words of planes, before they are unpacked), the entry
    // clamped to 0, the exit widened by BOX_EXIT_SCALE.
    bvec3 negative = lessThan(invDir, vec3(0.0));
    uvec3 nearWords = mix(uvec3(planesA.xyz), uvec3(planesA.w, planesB.xy), negative);
    uvec3 farWords = mix(uvec3(planesA.w, planesB.xy), uvec3(planesA.xyz), negative);
    vec4 nearX = wideChildPlaneDistances(nearWords.x, base.x, exponentBits.x, origin.x, invDir.x);
    vec4 nearY = wideChildPlaneDistances(nearWords.y, base.y, exponentBits.y, origin.y, invDir.y);
    vec4 nearZ = wideChildPlaneDistances(nearWords.z, base.z, exponentBits.z, origin.z, invDir.z);
    vec4 farX = wideChildPlaneDistances(farWords.x, base.x, exponentBits.x, origin.x, invDir.x);
    vec4 farY = wideChildPlaneDistances(farWords.y, base.y, exponentBits.y, origin.y, invDir.y);
    vec4 farZ = wideChildPlaneDistances(farWords.z, base.z, exponentBits.z, origin.z, invDir.z);
    vec4 tNear = maxOfNumbers(maxOfNumbers(nearX, nearY), maxOfNumbers(nearZ, vec4(0.0)));
    vec4 tFar = minOfNumbers(minOfNumbers(farX, farY), minOfNumbers(farZ, vec4(tMax))) * BOX_EXIT_SCALE;
    tEntry = tNear;
    bvec4 hit = lessThanEqual(tNear, tFar);
    uint exists = frame.w >> WIDE_CHILD_MASK_SHIFT;
    return exists & ((hit.x ? 1u : 0u) | (hit.y ? 2u : 0u) | (hit.z ? 4u : 0u) | (hit.w ? 8u : 0u));
}

// Of the children in `hits` (not empty), the one the ray enters first; ties go to the lower
// index. (Entry distances can be infinite, so no sentinel distance stands in for a miss.)
uint nearestChild(uint hits, vec4 tEntry) {
    uint nearest = 0u;
    float best = 0.0;
    bool found = false;
    for (uint c = 0u; c < WIDE_NODE_ARITY; ++c) {
        if ((hits & (1u << c)) != 0u && (!found || tEntry[c] < best)) {
            nearest = c;
            best = tEntry[c];
            found = true;
        }
    }
    return nearest;
}

#ifndef PENUMBRA_NODE_ADDRESS
#include "geometry/instances.glsl"
#endif

// Primitive i tested against the ray up to hit.t; where it is hit, `hit` becomes that hit
// and the result is true. An instance (PRIM_INSTANCE) is its group's tree, in its frame.
bool testPrimitive(uint i, vec3 origin, vec3 dir, inout Hit hit) {
    float t;
    vec2 uv;
    Primitive p = loadPrimitive(i);
#ifdef PENUMBRA_INSTANCES_GLSL
    if (hasPrimitive(PRIM_INSTANCE) && (p.typeAndNormals & PRIM_TYPE_MASK) == PRIM_INSTANCE)
        return testInstance(p.typeAndNormals >> 2, origin, dir, hit);
#endif
    bool found = intersectPrimitive(p, origin, dir, hit.t, t, uv);
#ifdef PENUMBRA_ALPHA_MASK_GLSL
    if (found && alphaCutOut(i, p, uv)) found = false;  // glTF MASK (textures/alpha_mask.glsl)
#endif
    if (found) {
        hit.t = t;
        hit.primitive = i;
        hit.uv = uv;
        hit.instance = NO_HIT;
    }
    return found;
}

// The primitives beside the tree (first and count) tested against the ray, as testPrimitives,
// apart from those in `ignore` (see traverse). A loop of the same count for every lane: a
// primitive that every lane's ray leaves out is a branch that no lane takes, which Mesa 24.3
// and later skip.
bool testBeside(uvec2 beside, vec3 origin, vec3 dir, bool anyHit, uvec2 ignore, inout Hit hit) {
    for (uint k = 0u; k < beside.y; ++k) {
        uint i = beside.x + k;
        if (i == ignore.x || i == ignore.y) continue;
        if (testPrimitive(i, origin, dir, hit) && anyHit) return true;
    }
    return false;
}

// Primitives [first, end) tested against the ray, `hit` kept as the closest found; true when
// `anyHit` and one is hit, so the query ends.
bool testPrimitives(uint first, uint end, vec3 origin, vec3 dir, bool anyHit, inout Hit hit) {
    for (uint i = first; i < end; ++i)
        if (testPrimitive(i, origin, dir, hit) && anyHit) return true;
    return false;
}

// The primitives of leaf `leaf` (offset | count << BVH_COUNT_SHIFT).
bool testLeaf(uint leaf, vec3 origin, vec3 dir, bool anyHit, inout Hit hit) {
    uint first = leaf & BVH_OFFSET_MASK;
    return testPrimitives(first, first + (leaf >> BVH_COUNT_SHIFT), origin, dir, anyHit, hit);
}

// Orders two children by key (entry distance), carrying their references: one
// compare-exchange of the sorting network in traverse.
void orderChildren(inout uint keyA, inout uint refA, inout uint keyB, inout uint refB) {
    bool swap = keyB < keyA;
    uint key = keyA, ref = refA;
    keyA = swap ? keyB : keyA;
    refA = swap ? refB : refA;
    keyB = swap ? key : keyB;
    refB = swap ? ref : refB;
}

#ifdef PENUMBRA_NODE_ADDRESS
// One step of the descent in traverse and tracePair, for the "_address" kernels: node `ref`
// tested against the ray; false where no child is hit. Otherwise the children hit are
// sorted by entry distance, all but the nearest pushed, farthest first, so that a popped
// child is taken up at once, and `ref` becomes the nearest.
bool descendOneNode(NodeQuadsAt nodes, TraversalStackAt stack, uint lastEntry, inout int sp, inout uint ref,
                    vec3 origin, vec3 invDir, float tMax) {
    vec4 tEntry;
    uvec4 refs;
    uint hits = intersectWideNode(nodes, ref, origin, invDir, tMax, tEntry, refs);
    if (hits == 0u) return false;
    // Entry distances are >= 0, so their bits order as the floats do; a child not hit sorts
    // last. A sorting network of five compare-exchanges (Knuth, TAOCP vol. 3, 5.3.4) puts
    // the children in order of entry, ties as the network leaves them
    // (host/bvh/traverse.cpp sorts with the same network).
    uvec4 key = floatBitsToUint(tEntry);
    key.x = (hits & 1u) != 0u ? key.x : 0xffffffffu;
    key.y = (hits & 2u) != 0u ? key.y : 0xffffffffu;
    key.z = (hits & 4u) != 0u ? key.z : 0xffffffffu;
    key.w = (hits & 8u) != 0u ? key.w : 0xffffffffu;
    orderChildren(key.x, refs.x, key.y, refs.y);
    orderChildren(key.z, refs.z, key.w, refs.w);
    orderChildren(key.x, refs.x, key.z, refs.z);
    orderChildren(key.y, refs.y, key.w, refs.w);
    orderChildren(key.y, refs.y, key.z, refs.z);
    // Sorted, the keys of the children hit come first, and a child's key is all ones only
    // where it was not hit (an entry distance is finite or +inf): three comparisons, where
    // a bit count of `hits` took lavapipe ten instructions of table lookups. An index past
    // the last entry is clamped to it (see TraversalStackAt).
    if (key.w != 0xffffffffu) stack.entries[min(uint(sp++), lastEntry)] = refs.w;
    if (key.z != 0xffffffffu) stack.entries[min(uint(sp++), lastEntry)] = refs.z;
    if (key.y != 0xffffffffu) stack.entries[min(uint(sp++), lastEntry)] = refs.y;
    ref = refs.x;
    return true;
}

// Whether child reference `ref` names an interior node (no primitive count).
bool isInteriorRef(uint ref) { return (ref >> BVH_COUNT_SHIFT) == 0u; }
#endif

// The loop behind both queries. From a node, the ray goes on to the nearest child it hits
// (for `anyHit` too: a blocked shadow ray meets its blocker sooner, 1.03-1.09x on a million
// triangles, docs/performance-history/round-13.md). What the stack keeps of the other children it hits depends on
// where the stack lives:
// - In memory through a device address (the "_address" kernels), one entry per child: the
//   children hit are sorted by entry distance and all but the nearest pushed, farthest
//   first, so a popped child is taken up at once. Up to three pushes a step cost three
//   masked scatters there, less than testing the parent's four boxes again when it comes
//   back: about 1.05x on a million triangles (0.97-1.09 over seven A/Bs, docs/performance-history/round-18.md).
// WIDE_NODE_ARITY - 1 entries per
//   node on the path from the root suffice (render/traversal_stacks.h sizes them).
// - In a local array (every other kernel), one entry per node: the node with its other
//   children's bits, tested again when popped with only those bits allowed, so a child that
//   now lies behind the closest hit found meanwhile fails its box test there. A push to a
//   local array is a loop over the SIMD lanes on lavapipe, and three of them per step cost
//   more than the test again (docs/performance-history/round-07.md). One entry per node on the path from the root, so
//   BVH_MAX_DEPTH entries suffice (host/bvh/wide.cpp: the wide tree is no deeper than the
//   binary one).
// With `anyHit` it returns at the first hit found. `anyHit` is a constant at both call
// sites below, so after inlining the compiler keeps a copy of the loop specialised for each
// query. Primitive ignore.x (NO_HIT: none) does not count in the inline tests and beside
// the tree; the tree's own tests need no such rule (traceAnyIgnoring says why).
// Primitive ignore.y is one that the caller knows the ray cannot meet: its test beside the
// tree is left out, which saves the test and changes nothing; the leaves and inline tests
// still test it, to no effect. The callers' reasons: a camera ray cannot meet a primitive
// out of the view (host/render/out_of_view.h), a ray cannot meet the flat primitive it
// leaves from (integrators/direct.comp, Shading).
bool traverse(vec3 origin, vec3 dir, float tMax, bool anyHit, uvec2 ignore, out Hit hit) {
    countRay();
    hit.t = tMax;
    hit.primitive = NO_HIT;
    hit.uv = vec2(0.0);
    hit.instance = NO_HIT;
    // A NaN or infinite ray misses. It must not enter the loop: NaN can make the slab test
    // pass for every box (min/max may drop NaN operands).
    if (!isFiniteVec(origin) || !isFiniteVec(dir)) return false;
#ifdef PENUMBRA_INLINE_GEOMETRY
    if (kInlineCount > 0u) {
        inlineClosest(origin, dir, ignore.x, hit);
        return hit.primitive != NO_HIT;
    }
#endif
    // The primitives beside the tree, in order, before it (host/bvh/bvh.h says which and
    // why): a large floor is then one test here, not a round of the loop below for most rays
    // and a level of the tree for the rest, 1.08x on a million triangles (docs/performance-history/round-22.md). A
    // uniform loop, usually of none; the tests are the leaves', so traceAnyIgnoring's
    // reasoning holds here too.
    uvec2 beside = bvhBesideRange();
    if (testBeside(beside, origin, dir, anyHit, ignore, hit)) return true;
    vec3 invDir = rayInverseDirection(dir);
    int sp = 0;
#ifdef PENUMBRA_NODE_ADDRESS
    // Entries: child references (offset | primCount << BVH_COUNT_SHIFT).
    TraversalStackAt stack = invocationStack(0u);
    uint lastEntry = bvhStackDepth() - 1u;
    // The nodes' address, read once here: read inside intersectWideNode, its push constants
    // were loaded again, with a bounds check, at every step (lavapipe 25.0's generated code),
    // as the stack's stores might alias them for all the compiler knows. With the pushes'
    // test in descendOneNode, 1.01x on a million triangles and 1.05x on mesh_light
    // (docs/performance-history/round-19.md).
    NodeQuadsAt nodes = NodeQuadsAt(bvhNodeAddress());
    uint ref = 0u;  // the root, an interior node
    while (true) {
        // Descend to a leaf, or until a node has no child hit.
        bool atLeaf = true;
        while (isInteriorRef(ref)) {
            if (!descendOneNode(nodes, stack, lastEntry, sp, ref, origin, invDir, hit.t)) {
                atLeaf = false;
                break;
            }
        }
        if (atLeaf && testLeaf(ref, origin, dir, anyHit, hit)) return true;
        if (sp == 0) break;
        --sp;
        ref = stack.entries[min(uint(sp), lastEntry)];
    }
#else
    uint stack[BVH_MAX_DEPTH];  // node | children still to visit << WIDE_STACK_MASK_SHIFT
    uint node = 0u, allowed = WIDE_ALL_CHILDREN;  // the root, every child
    while (true) {
        // Descend to a leaf, or until no allowed child is hit.
        bool atLeaf = false;
        uint leaf = 0u;
        while (true) {
            vec4 tEntry;
            uvec4 ref;
            uint hits = intersectWideNode(node, origin, invDir, hit.t, tEntry, ref) & allowed;
            if (hits == 0u) break;
            uint c = nearestChild(hits, tEntry);
            uint rest = hits & ~(1u << c);
            if (rest != 0u) {
                stack[sp] = node | (rest << WIDE_STACK_MASK_SHIFT);
                ++sp;
            }
            uint next = c == 0u ? ref.x : (c == 1u ? ref.y : (c == 2u ? ref.z : ref.w));
            if ((next >> BVH_COUNT_SHIFT) != 0u) {
                atLeaf = true;
                leaf = next;
                break;
            }
            node = next;
            allowed = WIDE_ALL_CHILDREN;
        }
        if (atLeaf && testLeaf(leaf, origin, dir, anyHit, hit)) return true;
        if (sp == 0) break;
        --sp;
        uint entry = stack[sp];
        node = entry & WIDE_STACK_NODE_MASK;
        allowed = entry >> WIDE_STACK_MASK_SHIFT;
    }
#endif
    return hit.primitive != NO_HIT;
}

// Nearest hit with t in (0, tMax), for camera and bounce rays.
bool traceClosest(vec3 origin, vec3 dir, float tMax, out Hit hit) {
    return traverse(origin, dir, tMax, false, uvec2(NO_HIT), hit);
}

// traceClosest with traverse's `ignore`: camera rays pass the primitive out of view as
// ignore.y (kernel_common.glsl, cameraRayIgnores).
bool traceClosestIgnoring(vec3 origin, vec3 dir, float tMax, uvec2 ignore, out Hit hit) {
    return traverse(origin, dir, tMax, false, ignore, hit);
}

// Whether anything is hit with t in (0, tMax): for shadow rays, stops at the first hit
// found, in no particular order.
bool traceAny(vec3 origin, vec3 dir, float tMax) {
    Hit hit;
    return traverse(origin, dir, tMax, true, uvec2(NO_HIT), hit);
}

// traceAny up to tMax = the distance at which the ray meets primitive ignore.x, or short of
// it, found by intersectPrimitive on the primitive as loadPrimitive reads it, with that
// primitive left out. The tree's leaves test the same data with the same code, so they find
// the same distance, never strictly below tMax; an inline test computes it from the
// constants, where the compiler folds the arithmetic differently and can land an ulp below,
// which would make the primitive hide itself. Leaving it out is exact: a quad is met once,
// and tMax is the nearer of a sphere's two distances. ignore.y: as in traverse.
bool traceAnyIgnoring(vec3 origin, vec3 dir, float tMax, uvec2 ignore) {
    Hit hit;
    return traverse(origin, dir, tMax, true, ignore, hit);
}


// An any-hit query handed to tracePair: traceAnyIgnoring's arguments, and whether there is
// one (`traced` false: none, which counts as a miss).
struct AnyHitRay {
    vec3 origin;
    vec3 dir;
    float tMax;
    bool traced;
    uvec2 ignore;
};

AnyHitRay noAnyHitRay() { return AnyHitRay(vec3(0.0), vec3(0.0, 0.0, 1.0), 0.0, false, uvec2(NO_HIT)); }

#ifdef PENUMBRA_NODE_ADDRESS
// Any-hit ray r taken up in tracePair's second slot: `hit` up to its tMax, its tests beside
// the tree made, and `invDir`. Returns whether those tests found a hit; `live` says whether
// the tree is still to walk (not where they found one, nor for a ray that is none or not
// finite, which misses, as in traverse).
bool startSecondSlot(AnyHitRay r, uvec2 beside, out Hit hit, out bool live, out vec3 invDir) {
    hit.t = r.tMax;
    hit.primitive = NO_HIT;
    hit.uv = vec2(0.0);
    hit.instance = NO_HIT;
    live = r.traced && isFiniteVec(r.origin) && isFiniteVec(r.dir);
    bool blocked = live && testBeside(beside, r.origin, r.dir, true, r.ignore, hit);
    live = live && !blocked;
    invDir = rayInverseDirection(r.dir);
    return blocked;
}

// Rays traversed together by one invocation: ray A for its closest hit with t in
// (0, tMaxA), as traceClosest, and the any-hit rays B and then C, as traceAnyIgnoring, one
// after the other in the second slot; `tracedA` false leaves ray A out (a miss). Returns
// whether A hit, and in `blockedB` / `blockedC` whether B / C did. Each loop below holds a
// step of each slot, so the CPU overlaps the two slots' dependent chains (a node's gather,
// its box tests, the stack): two chains in flight where traverse has one, as sixteen lanes
// bought over eight (docs/performance-history/round-15.md, two rays per invocation, 1.08-1.30x per step). A step runs
// only while some lane's ray needs it (Mesa 24.3 and later skip a branch no lane takes), so
// each ray costs the steps it would cost alone. Ray C takes the second slot where ray B
// ends, in that lane alone: the group then runs as long as its longest A or B-then-C,
// where a traversal of C after the loop would add its own longest lane (docs/performance-history/round-27.md). Each
// ray visits its nodes and primitives in the order traverse would, with the same tests, so
// its result is traverse's bit for bit: only the interleaving differs. The kernel traces a
// sample's camera ray together with the previous sample's first shadow ray and BRDF ray
// (integrators/direct.comp, addPixelSamples). Stacks 0 and 1 of the invocation.
bool tracePair(vec3 originA, vec3 dirA, float tMaxA, bool tracedA, uvec2 ignoreA, out Hit hitA, AnyHitRay b,
               AnyHitRay c, out bool blockedB, out bool blockedC) {
    hitA.t = tMaxA;
    hitA.primitive = NO_HIT;
    hitA.uv = vec2(0.0);
    hitA.instance = NO_HIT;
    if (tracedA) countRay();
    if (b.traced) countRay();
    if (c.traced) countRay();
    // As in traverse: a NaN or infinite ray misses, and must not enter the loop.
    bool liveA = tracedA && isFiniteVec(originA) && isFiniteVec(dirA);
    // The primitives beside the tree, before it, as in traverse.
    uvec2 beside = bvhBesideRange();
    if (liveA) testBeside(beside, originA, dirA, false, ignoreA, hitA);
    vec3 invDirA = rayInverseDirection(dirA);
    TraversalStackAt stackA = invocationStack(0u), stackB = invocationStack(1u);
    uint lastEntry = bvhStackDepth() - 1u;
    NodeQuadsAt nodes = NodeQuadsAt(bvhNodeAddress());
    uint refA = 0u, refB = 0u;  // the root, an interior node
    int spA = 0, spB = 0;
    // The second slot holds `ray`: B, then C once B has ended (`onC`). `blocked` is what the
    // ray in it found, `liveB` whether it still traverses.
    AnyHitRay ray = b;
    bool onC = false, liveB;
    Hit hitB;
    vec3 invDirB;
    bool blocked = startSecondSlot(b, beside, hitB, liveB, invDirB);
    blockedB = false;
    while (true) {
        // C takes the slot where B has ended (or had no ray): only in lanes with a C, so
        // that the block runs in few rounds.
        if (!liveB && !onC && c.traced) {
            blockedB = blocked;
            ray = c;
            onC = true;
            spB = 0;
            refB = 0u;
            blocked = startSecondSlot(c, beside, hitB, liveB, invDirB);
        }
        if (!liveA && !liveB) break;
        // Descend each ray to a leaf, or until a node of its has no child hit (traverse's
        // inner loop, for two).
        bool leafA = liveA, leafB = liveB;
        bool downA = liveA && isInteriorRef(refA), downB = liveB && isInteriorRef(refB);
        while (downA || downB) {
            if (downA) {
                leafA = descendOneNode(nodes, stackA, lastEntry, spA, refA, originA, invDirA, hitA.t);
                downA = leafA && isInteriorRef(refA);
            }
            if (downB) {
                leafB = descendOneNode(nodes, stackB, lastEntry, spB, refB, ray.origin, invDirB, hitB.t);
                downB = leafB && isInteriorRef(refB);
            }
        }
        // Both leaves in one loop, a primitive of each per round: the two rays' loads and
        // tests are independent work for the CPU to overlap. Each ray tests its leaf's
        // primitives in order, as testLeaf does.
        uint iA = refA & BVH_OFFSET_MASK, iB = refB & BVH_OFFSET_MASK;
        uint endA = leafA ? iA + (refA >> BVH_COUNT_SHIFT) : iA;
        uint endB = leafB ? iB + (refB >> BVH_COUNT_SHIFT) : iB;
        while (iA < endA || iB < endB) {
            if (iA < endA) testPrimitive(iA++, originA, dirA, hitA);
            if (iB < endB) {
                // Any hit ends the ray; its Hit is not read, so only the test is made.
                float t;
                vec2 uv;
                Primitive p = loadPrimitive(iB);
                bool found = intersectPrimitive(p, ray.origin, ray.dir, hitB.t, t, uv);
#ifdef PENUMBRA_ALPHA_MASK_GLSL
                if (found && alphaCutOut(iB, p, uv)) found = false;  // as testPrimitive
#endif
                if (found) {
                    blocked = true;
                    liveB = false;
                    endB = iB;
                }
                ++iB;
            }
        }
        if (liveA) {
            liveA = spA > 0;
            if (liveA) refA = stackA.entries[min(uint(--spA), lastEntry)];
        }
        if (liveB) {
            liveB = spB > 0;
            if (liveB) refB = stackB.entries[min(uint(--spB), lastEntry)];
        }
    }
    if (!onC) blockedB = blocked;
    blockedC = onC && blocked;
    return hitA.primitive != NO_HIT;
}
#endif

#endif
