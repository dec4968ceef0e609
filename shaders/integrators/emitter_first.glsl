// Emitter-first BRDF-sampled rays for the direct integrator: in a scene lit only by a few
// sphere and quad emitters (plus delta lights) and no environment, a BRDF-sampled ray
// counts only if the first surface it hits is one of those emitters. So the ray is tested
// against the emitters first, and only a ray that finds one traverses the BVH, as an any-hit
// query up to that emitter, instead of every ray taking a closest-hit traversal.
// Same estimator, same random numbers: the hit handed on is the emitter's, with t, uv and
// primitive as the closest-hit traversal finds them (the same intersectPrimitive), and it
// counts exactly when nothing lies strictly nearer, as for the closest hit. The host turns
// the path on (SPEC_EMITTER_FIRST = the light count) only where that holds and where it
// was measured to pay (render/emitter_first.cpp, docs/performance-history/round-04.md and
// docs/performance-history/round-05.md).
#ifndef PENUMBRA_EMITTER_FIRST_GLSL
#define PENUMBRA_EMITTER_FIRST_GLSL

#include "shared/types.h"
#include "common/math.glsl"
#include "common/specialization.glsl"
#include "geometry/bvh.glsl"
#include "lights/light_data.glsl"

bool emitterFirst() { return kEmitterFirstLights > 0u; }

// The nearest sphere or quad emitter along origin + t dir, t in (0, FLOAT_MAX), ignoring
// everything else in the scene. The light count is a specialization constant, so the loop
// has a fixed trip count and every lane loads the same light.
bool nearestEmitter(vec3 origin, vec3 dir, out Hit hit) {
    hit.t = FLOAT_MAX;
    hit.primitive = NO_HIT;
    hit.uv = vec2(0.0);
    hit.instance = NO_HIT;  // emitters are never instanced (they are copied)
    // As in traverse(): a NaN or infinite ray hits nothing.
    if (!isFiniteVec(origin) || !isFiniteVec(dir)) return false;
    for (uint i = 0u; i < kEmitterFirstLights; ++i) {
        Light light = loadLight(i);
        if (!lightIs(light, LIGHT_SPHERE) && !lightIs(light, LIGHT_QUAD)) continue;
        float t;
        vec2 uv;
        if (intersectPrimitive(loadPrimitive(light.first), origin, dir, hit.t, t, uv)) {
            hit.t = t;
            hit.primitive = light.first;
            hit.uv = uv;
        }
    }
    return hit.primitive != NO_HIT;
}

// The first hit of a BRDF-sampled ray as far as emission is concerned: the closest hit, or
// with the emitter-first path the nearest emitter (false: no emitter on the ray; the caller
// must then call emitterHidden before counting the emitter's light).
bool traceForEmission(vec3 origin, vec3 dir, out Hit hit) {
    if (emitterFirst()) return nearestEmitter(origin, dir, hit);
    return traceClosest(origin, dir, FLOAT_MAX, hit);
}

// The query that decides whether a surface strictly nearer than the emitter found by
// traceForEmission hides it, for emitterHidden or for a caller that traces it later. The
// emitter itself is left out: it is met at hit.t and nowhere nearer, and with the
// primitives inline its own test could land an ulp below. `leaving`: the flat primitive the
// ray leaves from, which it cannot meet (or NO_HIT).
AnyHitRay emitterHiddenRay(vec3 origin, vec3 dir, Hit hit, uint leaving) {
    return AnyHitRay(origin, dir, hit.t, true, uvec2(hit.primitive, leaving));
}

// Whether a surface strictly nearer than the emitter found by traceForEmission hides it;
// always false for a closest hit.
bool emitterHidden(vec3 origin, vec3 dir, Hit hit, uint leaving) {
    if (!emitterFirst()) return false;
    AnyHitRay ray = emitterHiddenRay(origin, dir, hit, leaving);
    return traceAnyIgnoring(ray.origin, ray.dir, ray.tMax, ray.ignore);
}

#endif
