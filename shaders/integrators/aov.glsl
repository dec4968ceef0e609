// The AOV layers' per-sample work (SCENE_FORMAT.md "AOVs (v3)"; the hook and the sums'
// layout: integrators/aov_sums.glsl, shared/aov.h). Each sample's camera ray is made again
// from the sample's own numbers, the same ray the integrator traced, and traced once more
// for its first hit: the layers average over exactly the image's samples (so they match it
// at silhouettes, as denoisers want) while the integrator's code stays as it was. The
// second trace costs only kernels with AOVs (kAovs != 0).
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

void addAovSample(inout AovSums a, uvec2 pixel, uint sampleIndex, vec3 radiance) {
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
    if (!aovWanted(AOV_ALBEDO | AOV_NORMAL | AOV_POSITION | AOV_DEPTH)) return;
    Rng rng = pixelRng(pixel, sampleIndex);
    vec3 origin, dir;
    cameraRay(pixel, rand2(rng), origin, dir);
    Hit hit;
    if (!traceClosestIgnoring(origin, dir, FLOAT_MAX, cameraRayIgnores(), hit)) return;  // a miss adds 0
    SurfacePoint sp = surfaceAt(hit, origin, dir);
    // dir is a unit vector: t is the distance from the eye.
    a.v[1].w += hit.t;
    a.v[2].w += 1.0;
    if (aovWanted(AOV_POSITION)) a.v[2].xyz += sp.position;
    if (aovWanted(AOV_NORMAL)) {
        // Facing the camera as the integrator shades it (geometry/surface.glsl).
        vec3 ng, ns;
        viewerSideNormals(sp, -dir, ng, ns);
        a.v[1].xyz += ns;
    }
    // Emitters have albedo 0 (SCENE_FORMAT.md).
    if (aovWanted(AOV_ALBEDO) && sp.light == NO_LIGHT)
        a.v[0].xyz += aovAlbedo(applyTextures(loadMaterial(sp.material), sp.material, sp.uv));
}

#endif
