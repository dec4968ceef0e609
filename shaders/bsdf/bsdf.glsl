// The BRDF of a material, dispatched on its type: each BRDF lives in its own file with its
// eval, pdf and sample (bsdf/diffuse.glsl, bsdf/phong.glsl, bsdf/pbr.glsl). Here: the checks that every
// BRDF shares (both directions above the surface) and the pdf returned with a sample.
// All directions are unit world-space vectors pointing away from the surface, and `n` is
// the shading normal already turned to the side of wo (two-sided materials). A type the
// scene lacks is compiled out (materialIs / hasMaterial, common/specialization.glsl).
#ifndef PENUMBRA_BSDF_GLSL
#define PENUMBRA_BSDF_GLSL

#include "shared/types.h"
#include "common/specialization.glsl"
#include "common/math.glsl"
#include "bsdf/diffuse.glsl"
#include "bsdf/phong.glsl"
#include "bsdf/pbr.glsl"

// f(wo, wi), zero when either direction is below the surface.
vec3 bsdfEval(Material m, vec3 n, vec3 wo, vec3 wi) {
    float cosI = dot(wi, n), cosO = dot(wo, n);
    if (cosI <= 0.0 || cosO <= 0.0) return vec3(0.0);
    if (materialIs(m, MATERIAL_PHONG)) return phongEval(m, n, wo, wi);
    if (materialIs(m, MATERIAL_PBR)) return pbrEval(m, n, wo, wi, cosO, cosI);
    return diffuseEval(m);
}

// Solid-angle density with which bsdfSample produces wi.
float bsdfPdf(Material m, vec3 n, vec3 wo, vec3 wi) {
    float cosTheta = dot(wi, n), cosO = dot(wo, n);
    if (cosTheta <= 0.0 || cosO <= 0.0) return 0.0;
    if (materialIs(m, MATERIAL_PHONG)) return phongPdf(m, n, wo, wi, cosTheta);
    if (materialIs(m, MATERIAL_PBR)) return pbrPdf(m, n, wo, wi, cosO, cosTheta);
    return diffusePdf(cosTheta);
}

// Draws wi; `lobe` in [0,1) picks the lobe, `u` drives the direction. Returns false when
// the sample falls below the surface (an estimate of zero, not a retry). pdf = bsdfPdf.
bool bsdfSample(Material m, vec3 n, vec3 wo, vec2 u, float lobe, out vec3 wi, out float pdf) {
    pdf = 0.0;
    wi = n;
    float cosO = dot(wo, n);
    if (cosO <= 0.0) return false;
    if (materialIs(m, MATERIAL_PHONG)) wi = phongSample(m, n, wo, u, lobe);
    else if (materialIs(m, MATERIAL_PBR)) wi = pbrSample(m, n, wo, u, lobe, cosO);
    else wi = diffuseSample(n, u);
    pdf = bsdfPdf(m, n, wo, wi);
    return pdf > 0.0;
}

#endif
