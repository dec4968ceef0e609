// Ambient occlusion (lecture, "Sampling the Cosine Term"; SCENE_FORMAT.md "ao"):
//   L(x) = albedo/pi * integral over H^2 of V(x, w) cos(theta) dw,
// one hemisphere direction per pixel sample, drawn uniformly (p = 1/(2 pi), estimate
// 2 albedo V cos) or cosine-weighted (p = cos/pi, estimate albedo V). Camera rays that
// miss everything see 1. cmake/EmbedShaders.cmake also compiles it as ao_inline<N>, with
// small scenes' primitives inline instead of the BVH (geometry/inline_geometry.glsl).
#version 450
#extension GL_GOOGLE_include_directive : require

#include "integrators/kernel_common.glsl"
#include "common/specialization.glsl"
// Before the traversal: its triangle hits run the alpha test (textures/alpha_mask.glsl).
#include "textures/alpha_mask.glsl"
#include "geometry/bvh.glsl"
#include "geometry/surface.glsl"
#include "sampling/warp.glsl"

#include "bsdf/materials.glsl"
#include "textures/textures.glsl"
#include "textures/normal_map.glsl"
#include "integrators/aov.glsl"

vec3 pixelSample(uvec2 pixel, uint sampleIndex, out AovFirstHit aov) {
    aov = aovMiss();
    Rng rng = pixelRng(pixel, sampleIndex);

    vec3 origin, dir;
    cameraRay(pixel, rand2(rng), origin, dir);
    Hit hit;
    if (!traceClosestIgnoring(origin, dir, FLOAT_MAX, cameraRayIgnores(), hit)) return vec3(1.0);
    SurfacePoint sp = surfaceAt(hit, origin, dir);
    sp.shadingNormal = normalMapped(sp);
    // Two-sided shading: use the side facing the viewer.
    vec3 ng = dot(sp.geometricNormal, dir) < 0.0 ? sp.geometricNormal : -sp.geometricNormal;
    vec3 ns = dot(sp.shadingNormal, ng) < 0.0 ? -sp.shadingNormal : sp.shadingNormal;
    Material m = applyTextures(loadMaterial(sp.material), sp.material, sp.uv);
    vec3 albedo = m.kd;
    if (kAovs != 0u) {
        // The AOV's normal is the direct integrator's viewer-side normal, the same in every kernel.
        vec3 aovNg, aovNs;
        viewerSideNormals(sp, -dir, aovNg, aovNs);
        aov = aovFirstHit(sp, hit.t, aovNs, m);
    }

    vec2 u = rand2(rng);
    vec3 local;
    float pdf;
    if (kAoSampling == AO_COSINE) {
        local = squareToCosineHemisphere(u);
        pdf = cosineHemispherePdf(local.z);
    } else {
        local = squareToUniformHemisphere(u);
        pdf = uniformHemispherePdf(local);
    }
    vec3 w = frameToWorld(local, ns);
    float cosTheta = local.z;
    vec3 L = vec3(0.0);
    // Directions below the geometric surface (possible with shading normals) are blocked.
    if (pdf > 0.0 && cosTheta > 0.0 && dot(w, ng) > 0.0 &&
        !traceAny(offsetRayOrigin(sp.position, ng), w, params.aoMaxDistance)) {
        L = albedo * INV_PI * cosTheta / pdf;
    }
    return L;
}
