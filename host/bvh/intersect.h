// Ray-primitive and ray-box intersection on the CPU, written in exactly the same form as
// shaders/geometry/intersect.glsl and bvh.glsl (same operations in the same order), so that
// tests compare like with like. Traversal lives in traverse.cpp, the tree in build.cpp.
//
// Contract for every test: the ray is origin + t * dir (dir need not be unit length, but is
// in practice); a hit counts only for t strictly inside (0, tMax).
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "shared/types.h"

namespace penumbra {

// Triangles and parallelograms (quads) in one test, as intersectFlat in intersect.glsl:
// both are p0 + u e1 + v e2, the triangle for u, v >= 0 and u + v <= 1, the parallelogram
// for u, v in [0, 1]. Möller & Trumbore 1997, "Fast, Minimum Storage Ray/Triangle
// Intersection", JGT 2(1). Chosen over the watertight test (Woop et al. 2013) because it
// needs no per-ray shear set-up and is cheaper on lavapipe; edges are inclusive, so a ray
// through a shared mesh edge can only miss both triangles through rounding, which is rare.
// Either side hits. uv = (u, v).
inline bool intersectFlat(glm::vec3 p0, glm::vec3 e1, glm::vec3 e2, bool parallelogram, glm::vec3 origin,
                          glm::vec3 dir, float tMax, float& t, glm::vec2& uv) {
    glm::vec3 pvec = glm::cross(dir, e2);
    float det = glm::dot(e1, pvec);
    if (det == 0.0f) return false;  // ray parallel to the plane (or degenerate shape)
    float invDet = 1.0f / det;
    glm::vec3 tvec = origin - p0;
    float u = glm::dot(tvec, pvec) * invDet;
    glm::vec3 qvec = glm::cross(tvec, e1);
    float v = glm::dot(dir, qvec) * invDet;
    float tHit = glm::dot(e2, qvec) * invDet;
    float extent = parallelogram ? glm::max(u, v) : u + v;
    if (!(u >= 0.0f && v >= 0.0f && extent <= 1.0f && tHit > 0.0f && tHit < tMax)) return false;
    t = tHit;
    uv = glm::vec2(u, v);
    return true;
}

// Triangle p0, p1, p2; uv = barycentrics of p1 and p2 (p = (1-u-v) p0 + u p1 + v p2).
inline bool intersectTriangle(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 origin, glm::vec3 dir,
                              float tMax, float& t, glm::vec2& uv) {
    return intersectFlat(p0, p1 - p0, p2 - p0, false, origin, dir, tMax, t, uv);
}

// Haines, Günther & Akenine-Möller 2019, "Precision Improvements for Ray/Sphere
// Intersection", Ray Tracing Gems ch. 7: the discriminant from the squared distance of the
// centre to the ray line (eq. 10, no catastrophic cancellation of b^2 - ac), and the two
// roots as c/q and q/a (eq. 13-15, Press et al.) so that the smaller one keeps its digits.
// Returns the nearer root inside (0, tMax): from inside the sphere, that is the far root.
inline bool intersectSphere(glm::vec3 centre, float radius, glm::vec3 origin, glm::vec3 dir, float tMax,
                            float& t) {
    glm::vec3 f = origin - centre;
    float a = glm::dot(dir, dir);
    float b = -glm::dot(f, dir);                // half of the usual b, sign flipped
    glm::vec3 l = f + (b / a) * dir;            // centre -> closest point of the ray line
    float discriminant = a * (radius * radius - glm::dot(l, l));  // = b^2 - a c, robustly
    if (discriminant < 0.0f) return false;
    float c = glm::dot(f, f) - radius * radius;
    float q = b + (b >= 0.0f ? 1.0f : -1.0f) * std::sqrt(discriminant);
    if (q == 0.0f) return false;  // tangent at the origin itself (b = 0, discriminant = 0)
    float t0 = c / q;
    float t1 = q / a;
    float tNear = glm::min(t0, t1);
    float tFar = glm::max(t0, t1);
    if (tNear > 0.0f && tNear < tMax) {
        t = tNear;
        return true;
    }
    if (tFar > 0.0f && tFar < tMax) {
        t = tFar;
        return true;
    }
    return false;
}

// Parallelogram corner + s edgeU + t edgeV, s, t in [0, 1]; uv = (s, t).
inline bool intersectQuad(glm::vec3 corner, glm::vec3 edgeU, glm::vec3 edgeV, glm::vec3 origin, glm::vec3 dir,
                          float tMax, float& t, glm::vec2& uv) {
    return intersectFlat(corner, edgeU, edgeV, true, origin, dir, tMax, t, uv);
}

inline bool intersectPrimitive(const gpu::Primitive& primitive, glm::vec3 origin, glm::vec3 dir, float tMax,
                               float& t, glm::vec2& uv) {
    uint32_t type = primitive.typeAndNormals & gpu::PRIM_TYPE_MASK;
    if (type == gpu::PRIM_TRIANGLE) return intersectTriangle(primitive.p0, primitive.p1, primitive.p2, origin, dir,
                                                             tMax, t, uv);
    if (type == gpu::PRIM_SPHERE) {
        uv = glm::vec2(0.0f);
        return intersectSphere(primitive.p0, primitive.p1.x, origin, dir, tMax, t);
    }
    if (type == gpu::PRIM_QUAD) return intersectQuad(primitive.p0, primitive.p1, primitive.p2, origin, dir, tMax,
                                                     t, uv);
    return false;
}

// The geometric front normal of `p` at x, a point on it (unnormalized for flat shapes).
inline glm::vec3 primitiveNormal(const gpu::Primitive& p, glm::vec3 x) {
    switch (p.typeAndNormals & gpu::PRIM_TYPE_MASK) {
        case gpu::PRIM_SPHERE: return x - p.p0;
        case gpu::PRIM_QUAD: return glm::cross(p.p1, p.p2);
        default: return glm::cross(p.p1 - p.p0, p.p2 - p.p0);
    }
}

// 1 / dir with zero components replaced by 1 / 1e-20 (sign kept for -0.0 as +), so the slab
// test below never forms 0 * inf = NaN and every inverse is finite.
inline glm::vec3 rayInverseDirection(glm::vec3 dir) {
    const float tiny = 1e-20f;
    glm::vec3 d;
    for (int i = 0; i < 3; ++i) d[i] = std::abs(dir[i]) < tiny ? (dir[i] < 0.0f ? -tiny : tiny) : dir[i];
    return 1.0f / d;
}

// Slab test in the sign-selected form of Williams et al. 2005 ("An Efficient and Robust
// Ray-Box Intersection Algorithm"): near planes chosen by the sign of the direction, so an
// inverted (empty) box always misses. tEntry = where the ray enters (clamped to 0). The exit is
// widened by BOX_EXIT_SCALE (shared/types.h, one constant for both sides).
inline bool intersectBox(glm::vec3 lo, glm::vec3 hi, glm::vec3 origin, glm::vec3 invDir, float tMax,
                         float& tEntry) {
    glm::vec3 nearP, farP;
    for (int i = 0; i < 3; ++i) {
        bool negative = invDir[i] < 0.0f;
        nearP[i] = negative ? hi[i] : lo[i];
        farP[i] = negative ? lo[i] : hi[i];
    }
    glm::vec3 tNear3 = (nearP - origin) * invDir;
    glm::vec3 tFar3 = (farP - origin) * invDir;
    float tNear = glm::max(glm::max(tNear3.x, tNear3.y), glm::max(tNear3.z, 0.0f));
    float tFar = glm::min(glm::min(tFar3.x, tFar3.y), glm::min(tFar3.z, tMax)) * gpu::BOX_EXIT_SCALE;
    tEntry = tNear;
    return tNear <= tFar;
}

}  // namespace penumbra
