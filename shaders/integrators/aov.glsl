// The AOV layers' per-sample work (SCENE_FORMAT.md "AOVs (v3)"; the hook and the sums'
// layout: integrators/aov_sums.glsl, shared/aov.h). The float layers average over exactly
// the image's samples (so they match it at silhouettes, as denoisers want): each kernel
// hands over the first hit its camera ray found (aovFirstHit, where it shades that hit).
// Only the ids trace a ray of their own, once per pixel. All of it costs only kernels with
// AOVs (kAovs != 0).
#ifndef PENUMBRA_AOV_GLSL
#define PENUMBRA_AOV_GLSL

#include "integrators/aov_sums.glsl"

bool aovWanted(uint bits) { return (kAovs & bits) != 0u; }

// The first surface's reflectance: diffuse albedo, phong kd + ks, pbr base_color, after
// textures (SCENE_FORMAT.md's table).
vec3 aovAlbedo(Material m) {
    if (materialIs(m, MATERIAL_PHONG)) return m.kd + m.ks;
    return m.kd;  // diffuse albedo and pbr base_color both live in kd (shared/types.h)
}

// `ns` from viewerSideNormals (geometry/surface.glsl), `m` after textures.
AovFirstHit aovFirstHit(SurfacePoint sp, float t, vec3 ns, Material m) {
    return AovFirstHit(true, t, sp.position, ns, sp.light == NO_LIGHT ? aovAlbedo(m) : vec3(0.0));
}

void addAovSample(inout AovSums a, uvec2 pixel, uint sampleIndex, vec3 radiance, AovFirstHit first) {
    if (kAovs == 0u) return;
    a.v[0].w += 1.0;
    if (aovWanted(AOV_VARIANCE)) {
        // The same guard as addSample: a non-finite estimate counts as 0.
        vec3 r = isFiniteVec(radiance) ? radiance : vec3(0.0);
        a.v[3].xyz += r * r;
    }
    // The ids come from the ray through the pixel's centre, traced with the first sample.
    if (aovWanted(AOV_IDS) && sampleIndex == 0u) {
        vec3 origin, dir;
        cameraRay(pixel, vec2(0.5), origin, dir);
        Hit hit;
        bool found = traceClosestIgnoring(origin, dir, FLOAT_MAX, cameraRayIgnores(), hit);
        a.v[3].w = uintBitsToFloat(found ? hit.primitive : NO_HIT);
    }
    if (!first.found) return;  // a miss adds 0
    a.v[1].w += first.t;
    a.v[2].w += 1.0;
    if (aovWanted(AOV_POSITION)) a.v[2].xyz += first.position;
    if (aovWanted(AOV_NORMAL)) a.v[1].xyz += first.normal;
    if (aovWanted(AOV_ALBEDO)) a.v[0].xyz += first.albedo;
}

#endif
