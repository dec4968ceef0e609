// Light selection "bvh" in the direct integrator (SCENE_FORMAT.md `light_selection`;
// host/render/light_bvh_arrays.h uploads it): a uniform choice among the lights at infinity
// (directional, environment) and the tree, then, for the tree, the descent of
// lights/light_bvh.glsl at the shading point, or for a small tree in a kernel with inline
// geometry the flat form of lights/light_flat.glsl. It replaces the full selection table of the
// light and mis strategies; the delta-only and continuous-only tables of bsdf and mixture
// stay the power ones. Compiled only where kLightBvh is set (SPEC_LIGHT_BVH).
#ifndef PENUMBRA_LIGHT_SELECTION_BVH_GLSL
#define PENUMBRA_LIGHT_SELECTION_BVH_GLSL

#include "shared/types.h"
#include "common/specialization.glsl"
#include "lights/lights.glsl"
#include "lights/light_bvh.glsl"
// Only the kernels with inline geometry hold a small tree's leaves as constants
// (render/light_flat.h); the others always descend the tree.
#ifdef PENUMBRA_INLINE_GEOMETRY
#include "lights/light_flat.glsl"
#else
bool lightFlatSelection() { return false; }
bool lightFlatAlone() { return false; }
uint sampleLightFlat(vec3 p, vec3 n, float u, out float pmf) { pmf = 0.0; return 0u; }
float lightFlatPmf(vec3 p, vec3 n, uint leaf) { return 0.0; }
uint lightFlatLight(uint leaf) { return 0u; }
uint lightFlatPrimitive(uint leaf) { return NO_HIT; }
uint lightFlatLeafHitBy(uint primitive) { return 0u; }
#endif

bool lightBvhSelection() { return kLightBvh != 0u; }

// The probability of each entry of the table beside the tree (pbrt-v4 BVHLightSampler:
// every light at infinity and the tree alike). Sampled and replayed pmfs both use it.
float lightBvhTableProbability() { return 1.0 / float(params.lightBvhTableCount); }

// A light chosen at x (shading normal n) with the 32-bit fraction `bits`: its index, the
// mesh triangle chosen (NO_HIT: the whole light) and its probability `pmf` (0: none).
uint drawLightBvh(vec3 x, vec3 n, uint bits, out uint triangle, out float pmf) {
    triangle = NO_HIT;
    pmf = 0.0;
    if (params.lightBvhTableCount == 0u) return 0u;
    float tablePmf = 1.0, rest = bitsToUnit(bits);
    // With no light at infinity the table holds the tree alone (probability 1): a small
    // tree's flat form then skips reading it.
    uint entry = lightFlatAlone()
                     ? NO_LIGHT
                     : selectLight(params.lightBvhTableOffset, params.lightBvhTableCount, bits, tablePmf, rest);
    if (!(tablePmf > 0.0)) return 0u;
    if (entry != NO_LIGHT) {
        pmf = lightBvhTableProbability();
        return entry;
    }
    if (lightFlatSelection()) {
        float flatPmf;
        uint leaf = sampleLightFlat(x, n, rest, flatPmf);
        triangle = lightFlatPrimitive(leaf);
        pmf = flatPmf * lightBvhTableProbability();
        return lightFlatLight(leaf);
    }
    float treePmf, unused;
    LightBvhItem item = loadLightBvhItem(params.lightBvhItems, sampleLightBvhTree(x, n, rest, treePmf, unused));
    triangle = item.primitive;  // ~0u = NO_HIT for every light but a mesh triangle
    pmf = treePmf * lightBvhTableProbability();
    return item.light;
}

// The probability that drawLightBvh at (x, n) chooses the emitter part that owns `primitive`
// (a sphere, a quad, or one triangle of a mesh light), replayed from its trail: the pmf
// that MIS weighs a BRDF-sampled ray hitting it with.
float lightBvhPrimitivePmf(vec3 x, vec3 n, uint primitive) {
    if (params.lightBvhItems == 0u) return 0.0;  // no tree
    if (lightFlatSelection()) return lightFlatPmf(x, n, lightFlatLeafHitBy(primitive)) * lightBvhTableProbability();
    return lightBvhTreePmf(x, n, loadLightBvhTrail(params.lightBvhTrails, primitive)) * lightBvhTableProbability();
}

// The probability that drawLightBvh chooses a light at infinity.
float lightBvhInfinitePmf() { return params.lightBvhTableCount == 0u ? 0.0 : lightBvhTableProbability(); }

#endif
