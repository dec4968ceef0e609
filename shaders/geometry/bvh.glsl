// Traversal of the flat BVH built by host/bvh/build.cpp: closest hit for camera and
// bounce rays, any hit for shadow rays. Declares the node and primitive buffers; what a hit
// means for shading (position, normals, material) is in surface.glsl.
// host/bvh/traverse.cpp mirrors both queries for the CPU tests.
#ifndef PENUMBRA_BVH_GLSL
#define PENUMBRA_BVH_GLSL

#include "shared/types.h"
#include "geometry/intersect.glsl"
#include "geometry/ray_count.glsl"

// Depth-first flat nodes: an interior node's left child is the next node, `offset` its
// right child; a leaf covers primitives[offset, offset + primCount).
layout(std430, binding = BINDING_NODES) readonly restrict buffer BvhNodes { BvhNode nodes[]; };
// Primitives in leaf order: Hit.primitive indexes this array.
layout(std430, binding = BINDING_PRIMITIVES) readonly restrict buffer Primitives { Primitive primitives[]; };

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
// here the lanes do their box tests together and their primitive tests together
// (measured 1.09x on the Cornell box, 1.18x on the default AO scene, 1.03x with 300k
// triangles: docs/PERFORMANCE.md).

// The loop behind both queries. Stack-based, nearest child first: both child boxes are
// tested, the far one is deferred with its entry distance and, for the closest hit,
// skipped on pop if a closer hit has been found meanwhile. With `anyHit` it returns at the
// first hit found, children in plain left-right order. The builder bounds leaf depth by
// BVH_MAX_DEPTH, and at most one node per level waits on the stack, so the fixed stack
// cannot overflow. `anyHit` is a constant at both call sites below, so after inlining the
// compiler keeps a copy of the loop specialised for each query.
bool traverse(vec3 origin, vec3 dir, float tMax, bool anyHit, out Hit hit) {
    countRay();
    hit.t = tMax;
    hit.primitive = NO_HIT;
    hit.uv = vec2(0.0);
    vec3 invDir = rayInverseDirection(dir);
    uint stackNode[BVH_MAX_DEPTH];
    float stackEntry[BVH_MAX_DEPTH];
    int sp = 0;
    float tEntry;
    if (!intersectBox(nodes[0].boundsMin, nodes[0].boundsMax, origin, invDir, tMax, tEntry)) return false;
    uint index = 0u;
    while (true) {
        // Descend to a leaf, or until both children are missed.
        bool atLeaf = false;
        while (true) {
            if (nodes[index].primCount > 0u) {
                atLeaf = true;
                break;
            }
            uint left = index + 1u;
            uint right = nodes[index].offset;
            float tLeft, tRight;
            bool hitLeft = intersectBox(nodes[left].boundsMin, nodes[left].boundsMax, origin, invDir, hit.t, tLeft);
            bool hitRight = intersectBox(nodes[right].boundsMin, nodes[right].boundsMax, origin, invDir, hit.t, tRight);
            if (!hitLeft && !hitRight) break;
            if (hitLeft && hitRight) {
                bool leftFirst = anyHit || tLeft <= tRight;
                stackNode[sp] = leftFirst ? right : left;
                stackEntry[sp] = leftFirst ? tRight : tLeft;
                ++sp;
                index = leftFirst ? left : right;
            } else {
                index = hitLeft ? left : right;
            }
        }
        if (atLeaf) {
            uint offset = nodes[index].offset;
            uint primCount = nodes[index].primCount;
            for (uint i = offset; i < offset + primCount; ++i) {
                float t;
                vec2 uv;
                if (intersectPrimitive(primitives[i], origin, dir, hit.t, t, uv)) {
                    hit.t = t;
                    hit.primitive = i;
                    hit.uv = uv;
                    if (anyHit) return true;
                }
            }
        }
        // Pop the next deferred node that can still hold something nearer than the hit.
        bool found = false;
        while (sp > 0) {
            --sp;
            if (anyHit || stackEntry[sp] <= hit.t * BOX_EXIT_SCALE) {
                index = stackNode[sp];
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
