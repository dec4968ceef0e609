// BRDFs of SCENE_FORMAT.md, each with eval, pdf and sample:
//   diffuse  f = kd / pi
//   phong    f = kd / pi + ks (n+2)/(2 pi) max(0, cos a)^n,  a = angle(wi, mirror of wo)
// (lecture, "Glossy Phong" and "BRDFs with Multiple Lobes"). Sampling picks the diffuse
// or glossy lobe with probability proportional to mean(kd) : mean(ks), then samples that
// lobe; the pdf is always the full mixture density, in solid angle.
// All directions are unit world-space vectors pointing away from the surface, and `n` is
// the shading normal already turned to the side of wo (two-sided materials).
#ifndef PENUMBRA_BSDF_GLSL
#define PENUMBRA_BSDF_GLSL

#include "shared/types.h"
#include "common/specialization.glsl"
#include "common/math.glsl"
#include "sampling/warp.glsl"

vec3 mirrorDirection(vec3 wo, vec3 n) { return 2.0 * dot(wo, n) * n - wo; }

// Probability of choosing the glossy lobe.
float glossyLobeProbability(Material m) {
    if (!materialIs(m, MATERIAL_PHONG)) return 0.0;
    float d = meanComponent(m.kd), s = meanComponent(m.ks);
    return d + s > 0.0 ? s / (d + s) : 0.0;
}

// f(wo, wi), zero when either direction is below the surface.
vec3 bsdfEval(Material m, vec3 n, vec3 wo, vec3 wi) {
    if (dot(wi, n) <= 0.0 || dot(wo, n) <= 0.0) return vec3(0.0);
    vec3 f = m.kd * INV_PI;
    if (materialIs(m, MATERIAL_PHONG)) {
        // cos^n through phongLobePdf ((n+1)/(2 pi) cos^n), not pow(): GLSL's pow is
        // exp2(n log2 cos) with log2 good only to ~2^-21 absolute near 1, i.e. up to ~1e-3
        // relative at n = 5000 (a 7e-5 bias in the albedo on lavapipe), and undefined for
        // pow(0, 0). Sharing the pdf's cos^n also keeps f / pdf exact for the glossy lobe.
        float cosAlpha = dot(wi, mirrorDirection(wo, n));
        if (cosAlpha > 0.0) f += m.ks * ((m.exponent + 2.0) / (m.exponent + 1.0) * phongLobePdf(cosAlpha, m.exponent));
    }
    return f;
}

// Solid-angle density with which bsdfSample produces wi.
float bsdfPdf(Material m, vec3 n, vec3 wo, vec3 wi) {
    float cosTheta = dot(wi, n);
    if (cosTheta <= 0.0 || dot(wo, n) <= 0.0) return 0.0;
    float glossy = glossyLobeProbability(m);
    float pdf = (1.0 - glossy) * cosTheta * INV_PI;
    if (hasMaterial(MATERIAL_PHONG) && glossy > 0.0) {
        // The lobe is sampled about the mirror direction and may dip below the surface;
        // those samples are discarded, so above the surface its density is the lobe's own.
        float cosAlpha = dot(wi, mirrorDirection(wo, n));
        if (cosAlpha > 0.0) pdf += glossy * phongLobePdf(cosAlpha, m.exponent);
    }
    return pdf;
}

// Draws wi; `lobe` in [0,1) picks the lobe, `u` drives the direction. Returns false when
// the sample falls below the surface (an estimate of zero, not a retry). pdf = bsdfPdf.
bool bsdfSample(Material m, vec3 n, vec3 wo, vec2 u, float lobe, out vec3 wi, out float pdf) {
    pdf = 0.0;
    wi = n;
    if (dot(wo, n) <= 0.0) return false;
    if (hasMaterial(MATERIAL_PHONG) && lobe < glossyLobeProbability(m)) {
        wi = frameToWorld(squareToPhongLobe(u, m.exponent), mirrorDirection(wo, n));
    } else {
        wi = frameToWorld(squareToCosineHemisphere(u), n);
    }
    pdf = bsdfPdf(m, n, wo, wi);
    return pdf > 0.0;
}

#endif
