// The render kernels' hook for the AOV layers (SCENE_FORMAT.md "AOVs (v3)"; the sums'
// layout in shared/aov.h): a pixel's AOV sums are loaded beside its radiance sum, each
// sample that the radiance sum counts is added to them too, with what the float layers take
// from its first hit (addAovSample, defined in integrators/aov.glsl, which needs the
// kernel's traversal and materials; each kernel fills AovFirstHit where it shades that
// hit, so no camera ray is traced twice), and they are
// stored back with it. With kAovs == 0 every line here is dead and the compiler removes it.
#ifndef PENUMBRA_AOV_SUMS_GLSL
#define PENUMBRA_AOV_SUMS_GLSL

#include "shared/aov.h"
#include "common/specialization.glsl"

layout(std430, binding = BINDING_AOV) restrict buffer AovBuffer { vec4 aovSums[]; };

struct AovSums {
    vec4 v[AOV_VEC4S];
};

// Written out, not looped: a loop would count against the loop budget of drivers that cut
// loops short (render/loop_budget.h).
AovSums loadAovSums(uint pixelIndex) {
    AovSums a = AovSums(vec4[AOV_VEC4S](vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0)));
    if (kAovs == 0u) return a;
    uint base = pixelIndex * AOV_VEC4S;
    a.v[0] = aovSums[base];
    a.v[1] = aovSums[base + 1u];
    a.v[2] = aovSums[base + 2u];
    a.v[3] = aovSums[base + 3u];
    return a;
}

void storeAovSums(uint pixelIndex, AovSums a) {
    if (kAovs == 0u) return;
    uint base = pixelIndex * AOV_VEC4S;
    aovSums[base] = a.v[0];
    aovSums[base + 1u] = a.v[1];
    aovSums[base + 2u] = a.v[2];
    aovSums[base + 3u] = a.v[3];
}

// What the float layers take from a sample's first hit (integrators/aov.glsl, aovFirstHit).
struct AovFirstHit {
    bool found;
    float t;        // distance from the eye (the camera ray's direction is a unit vector)
    vec3 position;
    vec3 normal;    // the shading normal facing the camera (geometry/surface.glsl, viewerSideNormals)
    vec3 albedo;    // 0 on emitters (SCENE_FORMAT.md)
};

AovFirstHit aovMiss() { return AovFirstHit(false, 0.0, vec3(0.0), vec3(0.0), vec3(0.0)); }

// Adds sample `sampleIndex` of `pixel`, whose radiance estimate was `radiance` and whose
// camera ray found `first`, to `a`.
void addAovSample(inout AovSums a, uvec2 pixel, uint sampleIndex, vec3 radiance, AovFirstHit first);

#endif
