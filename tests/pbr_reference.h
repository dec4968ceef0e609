// The `pbr` BRDF of SCENE_FORMAT.md v2 (glTF 2.0 Appendix B) in double precision on the CPU,
// written from the contract's formula and independent of shaders/bsdf/pbr.glsl: the tests'
// reference for the GPU's f, its sampling density and the closed-form / quadrature renders.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/glm.hpp>

#include "shared/types.h"

namespace penumbra::test {

struct PbrParams {
    glm::dvec3 baseColor{0.8};
    double metallic = 0.0;
    double roughness = 0.5;
    // alpha = roughness^2, clamped as the renderer does (PBR_MIN_ALPHA, docs/guide/materials.md).
    double alpha() const { return std::max(roughness * roughness, double(gpu::PBR_MIN_ALPHA)); }
};

inline double ggxD(double a, double cosH) {
    const double a2 = a * a, c2 = cosH * cosH;
    const double d = c2 * (a2 - 1.0) + 1.0;
    return a2 / (std::numbers::pi * d * d);
}

inline double smithV(double a, double cosO, double cosI) {
    const double a2 = a * a;
    return 0.5 / (cosI * std::sqrt(cosO * cosO * (1.0 - a2) + a2) + cosO * std::sqrt(cosI * cosI * (1.0 - a2) + a2));
}

inline double schlick(double f0, double vDotH) { return f0 + (1.0 - f0) * std::pow(1.0 - vDotH, 5.0); }

// f(wo, wi), 0 below the surface. The directions are normalized here: a float unit vector
// is unit only to ~1e-7, and 1 - (n.h)^2 near D's peak is smaller than that.
inline glm::dvec3 pbrF(const PbrParams& p, glm::dvec3 n, glm::dvec3 wo, glm::dvec3 wi) {
    n = glm::normalize(n);
    wo = glm::normalize(wo);
    wi = glm::normalize(wi);
    const double cosO = glm::dot(n, wo), cosI = glm::dot(n, wi);
    if (cosO <= 0.0 || cosI <= 0.0) return glm::dvec3(0.0);
    const glm::dvec3 h = glm::normalize(wo + wi);
    const double a = p.alpha(), vh = glm::dot(wo, h);
    const double dv = ggxD(a, glm::dot(n, h)) * smithV(a, cosO, cosI);
    const double fd = schlick(0.04, vh);
    glm::dvec3 f = (1.0 - p.metallic) * ((1.0 - fd) * p.baseColor / std::numbers::pi + glm::dvec3(fd * dv));
    for (int c = 0; c < 3; ++c) f[c] += p.metallic * schlick(p.baseColor[c], vh) * dv;
    return f;
}

// The sampling density the renderer documents (pbr.glsl, docs/design/contract-decisions.md): the specular lobe chosen
// with probability s / (s + d), s and d the lobes' Schlick weights at n.wo, its directions
// the reflected visible normals D_v(h) / (4 wo.h) (Heitz 2018); the rest cosine-weighted.
// `ndfInsteadOfVndf` swaps in the density of plain NDF sampling, D(h) (n.h) / (4 wo.h): a
// plausible but wrong pdf that the chi-square test must reject.
// The probability of sampling the specular lobe (pbr.glsl): its Schlick weight at n.wo over
// the sum of both lobes' weights.
inline double pbrSpecularProbability(const PbrParams& p, double cosO) {
    const double w = std::pow(1.0 - cosO, 5.0), fd = 0.04 + 0.96 * w;
    const double mean = (p.baseColor.x + p.baseColor.y + p.baseColor.z) / 3.0;
    const double s = (1.0 - p.metallic) * fd + p.metallic * (mean + (1.0 - mean) * w);
    const double d = (1.0 - p.metallic) * (1.0 - fd) * mean;
    return d > 0.0 ? s / (s + d) : 1.0;
}

inline double pbrPdf(const PbrParams& p, glm::dvec3 n, glm::dvec3 wo, glm::dvec3 wi, bool ndfInsteadOfVndf = false) {
    n = glm::normalize(n);
    wo = glm::normalize(wo);
    wi = glm::normalize(wi);
    const double cosO = glm::dot(n, wo), cosI = glm::dot(n, wi);
    if (cosO <= 0.0 || cosI <= 0.0) return 0.0;
    const double pSpec = pbrSpecularProbability(p, cosO);
    const glm::dvec3 h = glm::normalize(wo + wi);
    const double a = p.alpha(), D = ggxD(a, glm::dot(n, h)), vh = glm::dot(wo, h);
    double spec;
    if (ndfInsteadOfVndf) {
        spec = D * glm::dot(n, h) / (4.0 * vh);
    } else {
        const double g1 = 2.0 * cosO / (cosO + std::sqrt(a * a + (1.0 - a * a) * cosO * cosO));
        spec = g1 * vh * D / cosO / (4.0 * vh);
    }
    return pSpec * spec + (1.0 - pSpec) * cosI / std::numbers::pi;
}

}  // namespace penumbra::test
