// Ray-primitive intersection for triangles, spheres and quads; no scene access here (the
// BVH that calls these is bvh.glsl). host/bvh/intersect.h holds the same code for the CPU,
// operation for operation, and must change with this file.
//
// "Operation for operation" holds on every driver only because the tests' quantities are
// `precise` (SPIR-V NoContraction). Otherwise a driver may fuse a product and a sum into
// one fma, and NVIDIA's does. On an H200, rays starting just outside a sphere made the
// sphere test's c = |f|^2 - r^2 cancel, so the fused rounding moved t by over 1e-4 from the
// CPU's: the GPU was no less accurate, it just rounded differently (docs/performance-history/own-bench.md). The CPU
// side compiles with -ffp-contract=off for the same
// reason. On lavapipe 25.0 `precise` changes no instruction count (tools/bench/bench-instructions).
//
// `precise` alone is not enough for dot and cross, which a driver may compute with fmas
// inside them (Mesa 26's lavapipe does): the tests use preciseDot and preciseCross
// (common/math.glsl), whose order is glm's, as host/bvh/intersect.h computes them.
//
// Contract: the ray is origin + t * dir (dir need not be unit length, but is in practice);
// a hit counts only for t strictly inside (0, tMax). Both faces of triangles and quads hit.
#ifndef PENUMBRA_INTERSECT_GLSL
#define PENUMBRA_INTERSECT_GLSL

#include "shared/types.h"
#include "common/math.glsl"
#include "common/specialization.glsl"

// Triangles and parallelograms (quads) in one test: both are p0 + u e1 + v e2, the triangle
// for u, v >= 0 and u + v <= 1, the parallelogram for u, v in [0, 1]. Möller & Trumbore
// 1997, "Fast, Minimum Storage Ray/Triangle Intersection", JGT 2(1), with the bound on
// (u, v) chosen by the shape. Chosen over the watertight test (Woop et al. 2013) because it
// needs no per-ray shear set-up and is cheaper on lavapipe; edges are inclusive, so a ray
// through a shared mesh edge can miss both triangles only through rounding, which is rare.
// One test for both shapes matters on llvmpipe: a leaf's primitive test runs in SIMD
// lanes that execute every branch, so a scene with triangles and quads paid for both
// tests on every primitive.
// Computed without early returns: llvmpipe runs 8 rays in SIMD lanes, and one final test
// costs far less than a masked exit after each step (docs/performance-history/earlier-experiments.md).
// A parallel ray or degenerate shape gives det = 0, so u, v, tHit are infinite or NaN and
// every comparison below fails. uv = (u, v).
bool intersectFlat(vec3 p0, vec3 e1, vec3 e2, bool parallelogram, vec3 origin, vec3 dir, float tMax, out float t,
                   out vec2 uv) {
    precise vec3 pvec = preciseCross(dir, e2);
    precise float invDet = 1.0 / preciseDot(e1, pvec);
    precise vec3 tvec = origin - p0;
    precise float u = preciseDot(tvec, pvec) * invDet;
    precise vec3 qvec = preciseCross(tvec, e1);
    precise float v = preciseDot(dir, qvec) * invDet;
    precise float tHit = preciseDot(e2, qvec) * invDet;
    precise float extent = parallelogram ? max(u, v) : u + v;
    bool hit = u >= 0.0 && v >= 0.0 && extent <= 1.0 && tHit > 0.0 && tHit < tMax;
    t = hit ? tHit : 0.0;
    uv = hit ? vec2(u, v) : vec2(0.0);
    return hit;
}

// Triangle p0, p1, p2; uv = barycentrics of p1 and p2: position = (1 - u - v) p0 + u p1 + v p2.
bool intersectTriangle(vec3 p0, vec3 p1, vec3 p2, vec3 origin, vec3 dir, float tMax, out float t, out vec2 uv) {
    return intersectFlat(p0, p1 - p0, p2 - p0, false, origin, dir, tMax, t, uv);
}

// Haines, Günther & Akenine-Möller 2019, "Precision Improvements for Ray/Sphere
// Intersection", Ray Tracing Gems ch. 7: the discriminant from the squared distance of the
// centre to the ray line (eq. 10: no cancellation in b^2 - ac), the roots as c/q and q/a
// (eq. 13-15) so the smaller keeps its digits. Returns the nearer root inside (0, tMax):
// from inside the sphere that is the far root. Computed without early returns, like
// intersectFlat: a negative discriminant (sqrt of its clamp is then unused) and q = 0 (a
// tangent at the origin itself) fail the final test; host/bvh/intersect.h returns early
// with the same values.
bool intersectSphere(vec3 centre, float radius, vec3 origin, vec3 dir, float tMax, out float t) {
    precise vec3 f = origin - centre;
    precise float a = preciseDot(dir, dir);
    precise float b = -preciseDot(f, dir);                    // half the usual b, sign flipped
    precise vec3 l = f + (b / a) * dir;                       // centre -> closest point on the line
    precise float discriminant = a * (radius * radius - preciseDot(l, l));  // = b^2 - a c, robustly
    precise float c = preciseDot(f, f) - radius * radius;
    precise float q = b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(max(discriminant, 0.0));
    precise float t0 = c / q;
    precise float t1 = q / a;
    float tNear = min(t0, t1);
    float tFar = max(t0, t1);
    bool nearHit = tNear > 0.0 && tNear < tMax;
    bool farHit = tFar > 0.0 && tFar < tMax;
    bool hit = discriminant >= 0.0 && q != 0.0 && (nearHit || farHit);
    t = hit ? (nearHit ? tNear : tFar) : 0.0;
    return hit;
}

// Parallelogram corner + s edgeU + t edgeV, s, t in [0, 1]; uv = (s, t).
bool intersectQuad(vec3 corner, vec3 edgeU, vec3 edgeV, vec3 origin, vec3 dir, float tMax, out float t, out vec2 uv) {
    return intersectFlat(corner, edgeU, edgeV, true, origin, dir, tMax, t, uv);
}

// Dispatch on the PRIM_* type (shared/types.h) of a shape given by the points of
// Primitive. Sphere hits leave uv = (0, 0). Triangles and quads share intersectFlat,
// their edges picked by the type.
bool intersectShape(uint type, vec3 p0, vec3 p1, vec3 p2, vec3 origin, vec3 dir, float tMax, out float t,
                    out vec2 uv) {
    uv = vec2(0.0);
    t = 0.0;
    if (hasPrimitive(PRIM_SPHERE) && type == PRIM_SPHERE) return intersectSphere(p0, p1.x, origin, dir, tMax, t);
    if (!hasPrimitive(PRIM_TRIANGLE) && !hasPrimitive(PRIM_QUAD)) return false;
    bool quad = hasPrimitive(PRIM_QUAD) && (!hasPrimitive(PRIM_TRIANGLE) || type == PRIM_QUAD);
    vec3 e1 = quad ? p1 : p1 - p0;
    vec3 e2 = quad ? p2 : p2 - p0;
    return intersectFlat(p0, e1, e2, quad, origin, dir, tMax, t, uv);
}

bool intersectPrimitive(Primitive primitive, vec3 origin, vec3 dir, float tMax, out float t, out vec2 uv) {
    return intersectShape(primitive.typeAndNormals & PRIM_TYPE_MASK, primitive.p0, primitive.p1, primitive.p2, origin,
                          dir, tMax, t, uv);
}

// 1 / dir with components below 1e-20 in magnitude replaced by +-1e-20, so every inverse is
// finite and the slab test never forms 0 * inf = NaN.
vec3 rayInverseDirection(vec3 dir) {
    const float tiny = 1e-20;
    vec3 d = mix(dir, mix(vec3(tiny), vec3(-tiny), lessThan(dir, vec3(0.0))), lessThan(abs(dir), vec3(tiny)));
    return 1.0 / d;
}

// Slab test in the sign-selected form of Williams et al. 2005 ("An Efficient and Robust
// Ray-Box Intersection Algorithm"): the near planes are chosen by the sign of the direction,
// so an inverted (empty) box always misses. tEntry = where the ray enters (clamped to 0).
// The exit is widened by BOX_EXIT_SCALE (shared/types.h).
bool intersectBox(vec3 lo, vec3 hi, vec3 origin, vec3 invDir, float tMax, out float tEntry) {
    bvec3 negative = lessThan(invDir, vec3(0.0));
    vec3 tNear3 = (mix(lo, hi, negative) - origin) * invDir;
    vec3 tFar3 = (mix(hi, lo, negative) - origin) * invDir;
    float tNear = max(max(tNear3.x, tNear3.y), max(tNear3.z, 0.0));
    float tFar = min(min(tFar3.x, tFar3.y), min(tFar3.z, tMax)) * BOX_EXIT_SCALE;
    tEntry = tNear;
    return tNear <= tFar;
}

#endif
