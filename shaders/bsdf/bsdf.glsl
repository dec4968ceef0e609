// The BRDF of a material, dispatched on its type: each BRDF lives in its own file with its
// value and pdf, evaluated together (bsdf/bsdf_value.glsl), and its sampling
// (bsdf/diffuse.glsl, bsdf/phong.glsl, bsdf/pbr.glsl). Here: the checks that every BRDF
// shares (both directions above the surface) and the value returned with a sample.
// All directions are unit world-space vectors pointing away from the surface, and `n` is
// the shading normal already turned to the side of wo (two-sided materials). A type the
// scene lacks is compiled out (materialIs / hasMaterial, common/specialization.glsl).
#ifndef PENUMBRA_BSDF_GLSL
#define PENUMBRA_BSDF_GLSL

#include "shared/types.h"
#include "common/specialization.glsl"
#include "common/math.glsl"
#include "bsdf/bsdf_value.glsl"
#include "bsdf/diffuse.glsl"
#include "bsdf/phong.glsl"
#include "bsdf/pbr.glsl"

// f(wo, wi) and the solid-angle density with which bsdfSample produces wi (BsdfValue),
// zero when either direction is below the surface.
BsdfValue bsdfEvalPdf(Material m, vec3 n, vec3 wo, vec3 wi) {
    float cosI = dot(wi, n), cosO = dot(wo, n);
    if (cosI <= 0.0 || cosO <= 0.0) return BsdfValue(vec3(0.0), 0.0);
    if (materialIs(m, MATERIAL_PHONG)) return phongEvalPdf(m, n, wo, wi, cosI);
    if (materialIs(m, MATERIAL_PBR)) return pbrEvalPdf(m, n, wo, wi, cosO, cosI);
    return BsdfValue(diffuseEval(m), diffusePdf(cosI));
}

vec3 bsdfEval(Material m, vec3 n, vec3 wo, vec3 wi) { return bsdfEvalPdf(m, n, wo, wi).f; }
float bsdfPdf(Material m, vec3 n, vec3 wo, vec3 wi) { return bsdfEvalPdf(m, n, wo, wi).pdf; }

// Draws wi from the pair u. In a BRDF of two lobes u.x also picks the lobe and is then
// stretched back onto [0,1) within the lobe's share (sample reuse, sampling/warp.glsl,
// remapAfterChoice; the PBR book's BSDF::Sample_f, 3rd ed. section 14.1.6): each lobe's
// directions are distributed as with a number of their own, and a stratified pair
// stratifies the lobe choices and each lobe's directions together. Returns false when the
// sample falls below the surface (an estimate of zero, not a retry). value =
// bsdfEvalPdf(wi): f and the pdf of the returned direction.
bool bsdfSample(Material m, vec3 n, vec3 wo, vec2 u, out vec3 wi, out BsdfValue value) {
    value = BsdfValue(vec3(0.0), 0.0);
    wi = n;
    float cosO = dot(wo, n);
    if (cosO <= 0.0) return false;
    if (materialIs(m, MATERIAL_PHONG)) wi = phongSample(m, n, wo, u);
    else if (materialIs(m, MATERIAL_PBR)) wi = pbrSample(m, n, wo, u, cosO);
    else wi = diffuseSample(n, u);
    value = bsdfEvalPdf(m, n, wo, wi);
    return value.pdf > 0.0;
}

#endif
