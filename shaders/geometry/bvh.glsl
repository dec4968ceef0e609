// Traversal of the flat BVH built by host/bvh/build.cpp: closest hit for camera and
// bounce rays, any hit for shadow rays. Declares the node and primitive buffers; what a hit
// means for shading (position, normals, material) is in surface.glsl.
// host/bvh/traverse.cpp mirrors both queries for the CPU tests.
#ifndef PENUMBRA_BVH_GLSL
#define PENUMBRA_BVH_GLSL

#include "shared/types.h"
#include "common/math.glsl"
#include "geometry/intersect.glsl"
#include "geometry/ray_count.glsl"

// The tree in child pairs (shared/types.h): pair p holds the boxes of an interior node's two
// children and where each leads. The traversal reads pairs and primitives through texel
// buffers (texelFetch on a usamplerBuffer): llvmpipe (Mesa 22.3) turns a storage-buffer load
// inside a loop into a loop over the SIMD lanes with a bounds-check branch per component, a
// texel fetch into a branch-free gather of four words (measured: docs/PERFORMANCE.md,
// "Round 2: the data the kernels read").
layout(binding = BINDING_NODES) uniform usamplerBuffer pairTexels;
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

struct Hit {
    float t;           // ray parameter of the hit, in (0, tMax)
    uint primitive;    // index into primitives[], NO_HIT when nothing was hit
    vec2 uv;           // triangle: barycentrics of p1, p2; quad: (s, t); sphere: unused
};

// The traversal is "while-while" (Aila & Laine 2009, "Understanding the Efficiency of Ray
// Traversal on GPUs"): an inner loop descends through interior nodes until this ray reaches
// a leaf, and only then are the leaf's primitives tested. llvmpipe runs eight rays in SIMD
// lanes and executes every branch under a mask, so a single loop with an "interior or
// leaf" branch pays for box tests and a primitive test in every iteration of every lane;
// here the lanes do their box tests together and their primitive tests together (what it
// bought: docs/PERFORMANCE.md, "What each optimisation bought").

// The loop behind both queries. Stack-based, nearest child first: both child boxes of a
// pair are tested, the far one is deferred with its entry distance and, for the closest
// hit, skipped on pop if a closer hit has been found meanwhile. With `anyHit` it returns at
// the first hit found, children in plain order. The builder bounds leaf depth by
// BVH_MAX_DEPTH, and at most one child per level waits on the stack, so the fixed stack
// cannot overflow. `anyHit` is a constant at both call sites below, so after inlining the
// compiler keeps a copy of the loop specialised for each query.
bool traverse(vec3 origin, vec3 dir, float tMax, bool anyHit, out Hit hit) {
    countRay();
    hit.t = tMax;
    hit.primitive = NO_HIT;
    hit.uv = vec2(0.0);
    // A NaN or infinite ray misses. It must not enter the loop: NaN can make the slab test
    // pass for every box (min/max may drop NaN operands), and pair 0's empty entry leads
    // back to pair 0, so such a ray would never leave.
    if (!isFiniteVec(origin) || !isFiniteVec(dir)) return false;
    vec3 invDir = rayInverseDirection(dir);
    uint stackNode[BVH_MAX_DEPTH];  // offset | primCount << BVH_COUNT_SHIFT
    float stackEntry[BVH_MAX_DEPTH];
    int sp = 0;
    uint offset = 0u, count = 0u;  // an interior node whose children are pair 0: the root
    while (true) {
        // Descend to a leaf, or until both children are missed.
        bool atLeaf = false;
        while (true) {
            if (count > 0u) {
                atLeaf = true;
                break;
            }
            int texel = int(PAIR_TEXELS * offset);
            uvec4 lo0 = texelFetch(pairTexels, texel);
            uvec4 hi0 = texelFetch(pairTexels, texel + 1);
            uvec4 lo1 = texelFetch(pairTexels, texel + 2);
            uvec4 hi1 = texelFetch(pairTexels, texel + 3);
            float t0, t1;
            bool hit0 = intersectBox(uintBitsToFloat(lo0.xyz), uintBitsToFloat(hi0.xyz), origin, invDir, hit.t, t0);
            bool hit1 = intersectBox(uintBitsToFloat(lo1.xyz), uintBitsToFloat(hi1.xyz), origin, invDir, hit.t, t1);
            if (!hit0 && !hit1) break;
            uvec2 child0 = uvec2(lo0.w, hi0.w), child1 = uvec2(lo1.w, hi1.w);  // (offset, primCount)
            if (hit0 && hit1) {
                bool firstNear = anyHit || t0 <= t1;
                uvec2 far = firstNear ? child1 : child0;
                stackNode[sp] = far.x | (far.y << BVH_COUNT_SHIFT);
                stackEntry[sp] = firstNear ? t1 : t0;
                ++sp;
                uvec2 near = firstNear ? child0 : child1;
                offset = near.x;
                count = near.y;
            } else {
                uvec2 child = hit0 ? child0 : child1;
                offset = child.x;
                count = child.y;
            }
        }
        if (atLeaf) {
            for (uint i = offset; i < offset + count; ++i) {
                float t;
                vec2 uv;
                if (intersectPrimitive(loadPrimitive(i), origin, dir, hit.t, t, uv)) {
                    hit.t = t;
                    hit.primitive = i;
                    hit.uv = uv;
                    if (anyHit) return true;
                }
            }
        }
        // Pop the next deferred child that can still hold something nearer than the hit.
        bool found = false;
        while (sp > 0) {
            --sp;
            if (anyHit || stackEntry[sp] <= hit.t * BOX_EXIT_SCALE) {
                offset = stackNode[sp] & BVH_OFFSET_MASK;
                count = stackNode[sp] >> BVH_COUNT_SHIFT;
                found = true;
                break;
            }
        }
        if (!found) break;
    }
    return hit.primitive != NO_HIT;
}

// Nearest hit with t in (0, tMax), for camera and bounce rays.
bool traceClosest(vec3 origin, vec3 dir, float tMax, out Hit hit) { return traverse(origin, dir, tMax, false, hit); }

// Whether anything is hit with t in (0, tMax): for shadow rays, stops at the first hit
// found, in no particular order.
bool traceAny(vec3 origin, vec3 dir, float tMax) {
    Hit hit;
    return traverse(origin, dir, tMax, true, hit);
}

#endif
