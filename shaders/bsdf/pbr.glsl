// The `pbr` BRDF of SCENE_FORMAT.md v2: glTF 2.0 metallic-roughness (the glTF specification,
// Appendix B): GGX D, height-correlated Smith V, Schlick F, metallic blend. The specular
// lobe is sampled by the distribution of visible normals (Heitz 2018, in the spherical-cap
// form of Dupuy & Benyoub 2023), the diffuse lobe cosine-weighted; the pdf is the full
// mixture. Value with pdf, and sampling, side by side.
// Packing (shared/types.h): kd = base_color, ks.x = metallic, ks.y = roughness.
#ifndef PENUMBRA_BSDF_PBR_GLSL
#define PENUMBRA_BSDF_PBR_GLSL

#include "shared/types.h"
#include "common/math.glsl"
#include "sampling/warp.glsl"
#include "bsdf/bsdf_value.glsl"
#include "bsdf/diffuse.glsl"

// alpha = roughness^2 (glTF Appendix B), at least PBR_MIN_ALPHA (shared/types.h says why).
float pbrAlpha(Material m) { return max(m.ks.y * m.ks.y, PBR_MIN_ALPHA); }

// (1 - c)^5 of Schlick's approximation (Schlick 1994; glTF Appendix B).
float schlickWeight(float c) {
    float x = clamp(1.0 - c, 0.0, 1.0);
    float x2 = x * x;
    return x2 * x2 * x;
}

// GGX / Trowbridge-Reitz D(h) = a^2 / (pi ((n.h)^2 (a^2 - 1) + 1)^2) (glTF Appendix B;
// Walter et al. 2007, eq. 33), with the bracket written a^2 cos^2 + sin^2 and sin^2 taken
// from |n x h|^2: 1 - cos^2 cancels catastrophically where D peaks (h within ~alpha of n).
// `precise` here, in smithRoot, smithV and pbrEvalPdf's f: evaluated as f(wo, wi) and
// f(wi, wo), the same operations on the same values must give the same result. A driver
// free to fuse products into fmas can fuse differently at the two call sites. Near D's
// peak |n x h| is about alpha, so one product fused in the cross product moves D by about
// 2^-24 / alpha, relatively. That broke reciprocity on an NVIDIA H200 (docs/performance-history/own-bench.md). The
// dot and cross products are spelled out (preciseDot,
// preciseCross in common/math.glsl), since `precise` does not reach inside them (docs/performance-history/round-17.md).
float ggxD(float alpha, vec3 n, vec3 h) {
    precise float cosH = preciseDot(n, h);
    precise vec3 t = preciseCross(n, h);
    precise float a2 = alpha * alpha;
    precise float d = a2 * cosH * cosH + preciseDot(t, t);
    precise float D = a2 / (PI * d * d);
    return D;
}

// sqrt((n.v)^2 (1 - a^2) + a^2), written so that nothing cancels: the term of V and G1.
float smithRoot(float cosTheta, float a2) {
    precise float root = sqrt(cosTheta * cosTheta + a2 * (1.0 - cosTheta * cosTheta));
    return root;
}

// Height-correlated Smith visibility V = G2 / (4 n.l n.v) (glTF Appendix B; Heitz 2014,
// "Understanding the Masking-Shadowing Function", eq. 99), cosines > 0.
float smithV(float cosO, float cosI, float alpha) {
    precise float a2 = alpha * alpha;
    precise float denom = cosI * smithRoot(cosO, a2) + cosO * smithRoot(cosI, a2);
    // Only when both cosines are denormal: a measure-zero set, kept finite.
    return denom > 1e-30 ? 0.5 / denom : 0.0;
}

// Probability of sampling the specular lobe: its share of an estimate of the reflectance,
// each lobe's Fresnel weight at n.wo (the Schlick F at v.h = n.v). Positive wherever the
// specular lobe is (>= 0.04 (1 - metallic), and 1 when metallic = 1); below 1 wherever the
// diffuse lobe is, as SCENE_FORMAT.md requires of the mixture.
float pbrSpecularProbability(Material m, float cosO) {
    float w = schlickWeight(cosO);
    float metallic = m.ks.x;
    float dielectricF = 0.04 + 0.96 * w;
    float specular = (1.0 - metallic) * dielectricF + metallic * meanComponent(m.kd + (vec3(1.0) - m.kd) * w);
    float diffuse = (1.0 - metallic) * (1.0 - dielectricF) * meanComponent(m.kd);
    return diffuse > 0.0 ? specular / (specular + diffuse) : 1.0;
}

// Density of the specular lobe's reflected directions: D_v(h) / (4 |wo.h|) with
// D_v(h) = G1(wo) (wo.h) D(h) / (n.wo) (Heitz 2018, eq. 1 and 17) and Smith's
// G1 = 2 n.wo / (n.wo + smithRoot(n.wo)): D(h) / (2 (n.wo + smithRoot(n.wo))).
// d = D(h), from ggxD.
float pbrSpecularPdf(float d, float alpha, float cosO) {
    return d / (2.0 * (cosO + smithRoot(cosO, alpha * alpha)));
}

// f and the pdf (BsdfValue) for wo, wi above the surface (cosines cosO, cosI > 0), with
// D(h) taken once for both. f (glTF Appendix B):
//   f = (1 - metallic) [ (1 - F(0.04)) base/pi + F(0.04) D V ] + metallic F(base) D V;
// the pdf: the mixture of the cosine-weighted diffuse lobe and pbrSpecularPdf.
BsdfValue pbrEvalPdf(Material m, vec3 n, vec3 wo, vec3 wi, float cosO, float cosI) {
    float pSpecular = pbrSpecularProbability(m, cosO);
    float diffuseDensity = (1.0 - pSpecular) * diffusePdf(cosI);
    vec3 sum = wo + wi;
    float len = length(sum);
    if (!(len > 0.0)) return BsdfValue(vec3(0.0), diffuseDensity);
    vec3 h = sum / len;
    float alpha = pbrAlpha(m);
    float d = ggxD(alpha, n, h);
    precise float specular = d * smithV(cosO, cosI, alpha);
    // v.h = l.h = |wo + wi| / 2 for the half vector: symmetric in wo and wi (reciprocity).
    float w = schlickWeight(0.5 * len);
    float dielectricF = 0.04 + 0.96 * w;
    vec3 metalF = m.kd + (vec3(1.0) - m.kd) * w;
    float metallic = m.ks.x;
    precise vec3 f = (1.0 - metallic) * ((1.0 - dielectricF) * m.kd * INV_PI + vec3(dielectricF * specular)) +
             metallic * metalF * specular;
    return BsdfValue(f, diffuseDensity + pSpecular * pbrSpecularPdf(d, alpha, cosO));
}

// A visible normal of GGX for the local direction v (z up), isotropic alpha: Dupuy &
// Benyoub 2023, "Sampling Visible GGX Normals with Spherical Caps" (Listing 3), the same
// distribution as Heitz 2018 ("Sampling the GGX Distribution of Visible Normals", JCGT
// 7(4)): stretch v into the hemisphere configuration, sample the spherical cap z in
// (-v.z, 1] uniformly, add v, unstretch. The cap's z and 1 - z^2 = (1 - z)(1 + z) come
// straight from u, so the tail of the distribution (u.y near 1) keeps its float precision
// where Heitz's sqrt(1 - t1^2 - t2^2) rounds to 0 (a horizontal normal, then a sample below
// the surface that the exact distribution does not have).
vec3 sampleGgxVndf(vec3 v, float alpha, vec2 u) {
    vec3 vh = normalize(vec3(alpha * v.x, alpha * v.y, v.z));
    float phi = TWO_PI * u.x;
    float z = (1.0 - u.y) * (1.0 + vh.z) - vh.z;
    float sinTheta = sqrt(clamp((1.0 - z) * (1.0 + z), 0.0, 1.0));
    vec3 h = vec3(sinTheta * cos(phi), sinTheta * sin(phi), z) + vh;
    return normalize(vec3(alpha * h.x, alpha * h.y, max(h.z, 0.0)));
}

// The direction only; bsdf/bsdf.glsl evaluates the mixture pdf at it. A specular sample
// reflected below the surface is declined there (pdf 0). u.x picks the lobe and is reused
// for its direction (bsdfSample).
vec3 pbrSample(Material m, vec3 n, vec3 wo, vec2 u, float cosO) {
    float specular = pbrSpecularProbability(m, cosO);
    bool chooseSpecular = u.x < specular;
    u.x = remapAfterChoice(u.x, specular);
    if (chooseSpecular) {
        vec3 v = frameToLocal(wo, n);
        vec3 h = sampleGgxVndf(v, pbrAlpha(m), u);
        return frameToWorld(2.0 * dot(v, h) * h - v, n);
    }
    return diffuseSample(n, u);
}

#endif
