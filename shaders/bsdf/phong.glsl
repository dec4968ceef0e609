// The `phong` BRDF of SCENE_FORMAT.md, normalized Phong (lecture, "Glossy Phong" and "BRDFs
// with Multiple Lobes"): f = kd / pi + ks (n+2)/(2 pi) max(0, cos a)^n, a = angle(wi, mirror
// of wo). Sampling picks the diffuse or glossy lobe with probability proportional to
// mean(kd) : mean(ks); the pdf is the full mixture. Value with pdf, and sampling, side by side.
#ifndef PENUMBRA_BSDF_PHONG_GLSL
#define PENUMBRA_BSDF_PHONG_GLSL

#include "shared/types.h"
#include "common/math.glsl"
#include "sampling/warp.glsl"
#include "bsdf/bsdf_value.glsl"
#include "bsdf/diffuse.glsl"

vec3 mirrorDirection(vec3 wo, vec3 n) { return 2.0 * dot(wo, n) * n - wo; }

// Probability of choosing the glossy lobe.
float phongGlossyProbability(Material m) {
    float d = meanComponent(m.kd), s = meanComponent(m.ks);
    return d + s > 0.0 ? s / (d + s) : 0.0;
}

// f and the pdf (BsdfValue) for wo, wi above the surface (cosThetaI = n . wi > 0). The
// lobe's cos^n is taken once for both, through phongLobePdf ((n+1)/(2 pi) cos^n), not
// pow(): GLSL's pow is exp2(n log2 cos) with log2 good only to ~2^-21 absolute near 1, i.e.
// up to ~1e-3 relative at n = 5000 (a 7e-5 bias in the albedo on lavapipe), and undefined
// for pow(0, 0). Sharing it also keeps f / pdf exact for the glossy lobe.
BsdfValue phongEvalPdf(Material m, vec3 n, vec3 wo, vec3 wi, float cosThetaI) {
    float glossy = phongGlossyProbability(m);
    float cosAlpha = dot(wi, mirrorDirection(wo, n));
    // The lobe is sampled about the mirror direction and may dip below the surface; those
    // samples are discarded, so above the surface its density is the lobe's own.
    float lobe = cosAlpha > 0.0 ? phongLobePdf(cosAlpha, m.exponent) : 0.0;
    vec3 f = diffuseEval(m) + m.ks * ((m.exponent + 2.0) / (m.exponent + 1.0) * lobe);
    float pdf = (1.0 - glossy) * cosThetaI * INV_PI + glossy * lobe;  // the diffuse lobe cosine-weighted
    return BsdfValue(f, pdf);
}

// The direction only; bsdf/bsdf.glsl evaluates the mixture pdf at it. u.x picks the lobe
// and is reused for its direction (bsdfSample).
vec3 phongSample(Material m, vec3 n, vec3 wo, vec2 u) {
    float glossy = phongGlossyProbability(m);
    bool chooseGlossy = u.x < glossy;
    u.x = remapAfterChoice(u.x, glossy);
    if (chooseGlossy) return frameToWorld(squareToPhongLobe(u, m.exponent), mirrorDirection(wo, n));
    return diffuseSample(n, u);
}

#endif
