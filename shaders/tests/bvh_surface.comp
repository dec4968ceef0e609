// Test entry point for geometry/surface.glsl: a first ray hits a surface, surfaceAt gives
// the point and normal, and a second ray leaves it from offsetRayOrigin in a given local
// direction (z > 0 = away from the surface on the chosen side). Reports whether the second
// ray hits its own primitive again (it never should) and what it hits in the scene.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/types.h"
#include "common/math.glsl"
#include "geometry/surface.glsl"

layout(local_size_x = 64) in;

struct SurfaceCase {
    vec4 origin;     // xyz: first ray origin
    vec4 dir;        // xyz: first ray direction
    vec4 outLocal;   // xyz: second ray direction in the (t, b, n) frame of the side normal;
                     // w > 0: leave on the side the first ray came from, w < 0: the other side
};
struct SurfaceResult {
    uint firstPrimitive;   // what the first ray hit (NO_HIT if nothing)
    uint selfHit;          // 1 if the second ray hits firstPrimitive again
    uint secondPrimitive;  // closest hit of the second ray (NO_HIT if nothing)
    float offset;          // |offsetRayOrigin(p, n) - p|
    vec4 position;         // xyz: surfaceAt position, w: self-hit t (if any)
    vec4 normal;           // xyz: geometric normal
    vec4 shading;          // xyz: shading normal
};

layout(std430, binding = 0) readonly restrict buffer Cases { SurfaceCase cases[]; };
layout(std430, binding = 1) writeonly restrict buffer Results { SurfaceResult results[]; };
// tests/test_bvh.cpp pushes bvh_trace.comp's constants to both: the primitives beside the
// tree are its last two.
layout(push_constant) uniform Push {
    uint caseCount;
    layout(offset = 24) uint besideFirst;
    uint besideCount;
};

uvec2 bvhBesideRange() { return uvec2(besideFirst, besideCount); }

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= caseCount) return;
    SurfaceResult result;
    result.firstPrimitive = NO_HIT;
    result.selfHit = 0u;
    result.secondPrimitive = NO_HIT;
    result.offset = 0.0;
    result.position = vec4(0.0);
    result.normal = vec4(0.0);
    result.shading = vec4(0.0);
    vec3 origin = cases[i].origin.xyz;
    vec3 dir = cases[i].dir.xyz;
    Hit hit;
    if (traceClosest(origin, dir, FLOAT_MAX, hit)) {
        SurfacePoint sp = surfaceAt(hit, origin, dir);
        vec3 n = dot(sp.geometricNormal, dir) < 0.0 ? sp.geometricNormal : -sp.geometricNormal;
        if (cases[i].outLocal.w < 0.0) n = -n;
        vec3 newDir = frameToWorld(cases[i].outLocal.xyz, n);
        vec3 newOrigin = offsetRayOrigin(sp.position, n);
        float t;
        vec2 uv;
        result.firstPrimitive = hit.primitive;
        result.selfHit = intersectPrimitive(primitives[hit.primitive], newOrigin, newDir, FLOAT_MAX, t, uv) ? 1u : 0u;
        Hit second;
        result.secondPrimitive = traceClosest(newOrigin, newDir, FLOAT_MAX, second) ? second.primitive : NO_HIT;
        result.offset = length(newOrigin - sp.position);
        result.position = vec4(sp.position, result.selfHit != 0u ? t : 0.0);
        result.normal = vec4(sp.geometricNormal, 0.0);
        result.shading = vec4(sp.shadingNormal, 0.0);
    }
    results[i] = result;
}
