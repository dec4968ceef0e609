// Strategy "ris" of the direct integrator (SCENE_FORMAT.md; docs/guide/integrators.md derives
// it): resampled importance sampling of direct light. Each of N1 = light_samples draws takes
// M = ris_candidates light candidates and N2 = bsdf_samples BRDF candidates, keeps one in
// proportion to its resampling weight and traces one shadow ray for it. Included by
// integrators/direct.comp, whose Shading, drawAnyLight, lightShadowRay and incidentEmission
// it uses; only a kernel with kStrategy == STRATEGY_RIS runs (and so keeps) any of it.
//
// Sources: Talbot, Cline and Egbert 2005, "Importance Resampling for Global Illumination"
// (RIS); Bitterli et al. 2020, "Spatiotemporal reservoir resampling for real-time ray tracing
// with dynamic direct lighting", section 4 and Algorithm 2 (RIS with MIS weights, streaming
// reservoir); Lin et al. 2022, "Generalized Resampled Importance Sampling" (GRIS), section 5
// (the generalized balance heuristic as resampling weights).
//
// The estimator. Candidates x_i come from two techniques t: light sampling L (n_L = M
// candidates, density p_L = light-selection pmf x the light's solid-angle density) and BRDF
// sampling B (n_B = N2, density p_B = the BRDF's solid-angle density). The target is
// p^(x) = luminance(f Le cos), unshadowed. Generalized balance weights
//   m_t(x) = p_t(x) / (n_L p_L(x) + n_B p_B(x)),   sum over all candidates of m = 1,
// give each candidate the resampling weight
//   w_i = m_t(x_i) p^(x_i) / p_t(x_i) = p^(x_i) / (n_L p_L(x_i) + n_B p_B(x_i)),
// one candidate y is kept with probability w_y / sum w, and the draw's estimate is
//   f(y) Le(y) cos V(y) / p^(y) * sum_i w_i,
// unbiased wherever the m sum to 1 on the integrand's support (GRIS, theorem 1). The
// densities in the denominator are those mis weighs with: for a BRDF candidate the full
// selection pmf (the tree's, replayed, under "bvh") times the solid-angle density of the
// light it hits, or of the environment where it escapes (incidentEmission).
// Delta lights (point, spot, directional) are one point each of the domain, with counting
// measure: only light sampling makes them (p_B = 0 there), with "density" their selection
// pmf, so their w = p^ / (M pmf). Continuous and delta candidates then share one sum of
// weights, each against the measure of its own part of the domain.
// A BRDF candidate's traced ray knows its first hit: one that meets no emitter (or an
// occluder first) has Le = 0 there, p^ = 0, and is never kept; a kept one needs no shadow
// ray. The light candidates' p^ leaves visibility out; the kept one's shadow ray puts it in.
// Where a light point is hidden, its integrand is 0, so that the BRDF density used there
// (that of the direction, not of the hidden point) leaves the estimate unbiased.
#ifndef PENUMBRA_RIS_GLSL
#define PENUMBRA_RIS_GLSL

// p^: the luminance of an unshadowed contribution (Rec. 709 weights, as the many-lights
// literature resamples by). Positive wherever any channel is, so p^ > 0 wherever f != 0.
float risTarget(vec3 contribution) { return dot(contribution, vec3(0.2126, 0.7152, 0.0722)); }

// A candidate: its unshadowed f Le cos, its p^, its resampling weight w (0: none), and the
// shadow ray that decides its visibility if kept (none for a BRDF candidate: its ray was
// traced).
struct RisCandidate {
    vec3 contribution;
    float target;
    float weight;
    AnyHitRay ray;
};

RisCandidate noRisCandidate() { return RisCandidate(vec3(0.0), 0.0, 0.0, noAnyHitRay()); }

// The candidate's weight p^ / density, or none where that is not a positive finite number
// (the NaN / Inf guard: such a candidate is dropped rather than kept).
RisCandidate weighted(RisCandidate c, float density) {
    c.weight = c.target / density;
    if (!(c.target > 0.0) || !(c.weight > 0.0) || isinf(c.weight)) return noRisCandidate();
    return c;
}

// A light candidate: a light from the full selection (drawAnyLight, as mis draws it) and a
// point on it from the light's own sampling. nLight = M, nBsdf = N2.
RisCandidate risLightCandidate(Shading s, float nLight, float nBsdf, inout Rng rng) {
    float pmf;
    vec3 u;
    uint triangle;
    uint index = drawAnyLight(s, rng, pmf, u, triangle);
    if (!(pmf > 0.0)) return noRisCandidate();
    LightSample ls;
    bool sampled = lightBvhSelection() ? sampleLightPart(index, triangle, s.origin, s.ns, u, lightModes(), ls)
                                       : sampleLight(index, s.origin, s.ns, u, lightModes(), ls);
    if (!sampled) return noRisCandidate();
    BsdfValue b = bsdfEvalPdf(s.m, s.ns, s.wo, ls.wi);
    RisCandidate c = noRisCandidate();
    c.contribution = cosineWeighted(s, ls.wi, b.f) * ls.radiance;
    c.target = risTarget(c.contribution);
    c.ray = lightShadowRay(s, index, ls);
    // A delta light: only light sampling makes it, with probability pmf (the header says why).
    float density = ls.isDelta ? nLight * pmf : nLight * pmf * ls.pdf + nBsdf * b.pdf;
    return weighted(c, density);
}

// A BRDF candidate: a BRDF-sampled direction and the emission its ray meets first.
RisCandidate risBsdfCandidate(Shading s, float nLight, float nBsdf, inout Rng rng) {
    vec3 wi;
    BsdfValue b;
    if (!bsdfSample(s.m, s.ns, s.wo, rand2(rng), wi, b)) return noRisCandidate();
    vec3 fc = cosineWeighted(s, wi, b.f);
    if (fc == vec3(0.0)) return noRisCandidate();
    float pLight;
    AnyHitRay none;
    // Not waiting: an emitter found first (emitter_first.glsl) is checked for occluders here.
    vec3 Le = incidentEmission(s, wi, 1.0, lightBvhSelection(), unknownQuadDensity(), false, pLight, none);
    RisCandidate c = noRisCandidate();
    c.contribution = fc * Le;
    c.target = risTarget(c.contribution);
    return weighted(c, nLight * pLight + nBsdf * b.pdf);
}

// Weighted reservoir sampling of one candidate from a stream (Chao 1982; Bitterli et al. 2020,
// Algorithm 2): after each update, `kept` is any one candidate seen so far with probability
// its weight over `weightSum`. Each update takes a fresh number u in [0, 1).
struct RisReservoir {
    RisCandidate kept;
    float weightSum;
};

void risUpdate(inout RisReservoir r, RisCandidate c, float u) {
    r.weightSum += c.weight;
    if (u * r.weightSum < c.weight) r.kept = c;
}

// One draw: M light and N2 BRDF candidates, one kept. Returns its term,
// f Le cos / p^ * sum w, with the shadow ray to trace (a light candidate's), or, with `seen`
// true, a term already known to be visible (a BRDF candidate's, no ray).
ShadowedTerm risDraw(Shading s, inout Rng rng, out bool seen) {
    seen = false;
    float nLight = float(kRisCandidates), nBsdf = float(kBsdfSamples);
    RisReservoir r = RisReservoir(noRisCandidate(), 0.0);
    // Every candidate takes its own dimensions, in a fixed order (light candidates first, as
    // mis draws its light samples first), whether or not it gets a weight.
    for (uint i = 0u; i < kRisCandidates; ++i) {
        RisCandidate c = risLightCandidate(s, nLight, nBsdf, rng);
        risUpdate(r, c, rand1(rng));
    }
    for (uint i = 0u; i < kBsdfSamples; ++i) {
        RisCandidate c = risBsdfCandidate(s, nLight, nBsdf, rng);
        risUpdate(r, c, rand1(rng));
    }
    ShadowedTerm term = noShadowedTerm();
    if (!(r.weightSum > 0.0) || !(r.kept.target > 0.0)) return term;
    vec3 value = r.kept.contribution * (r.weightSum / r.kept.target);
    if (!isFiniteVec(value)) return term;
    term.value = value;
    term.ray = r.kept.ray;
    seen = !term.ray.traced;
    return term;
}

// The reflected light of N1 draws, averaged, apart from the first draw's light term, which
// it leaves in `waiting` (with its shadow ray traced, or for the kernel that traces it with
// the next sample's camera ray, not yet), as the light strategy leaves its first sample.
vec3 risReflectedRadiance(Shading s, inout Rng rng, inout ShadowedTerm waiting) {
    vec3 L = vec3(0.0);
    for (uint i = 0u; i < kLightSamples; ++i) {
        bool seen;
        ShadowedTerm term = risDraw(s, rng, seen);
        term.value /= float(kLightSamples);
        if (seen) {
            L += term.value;
            continue;
        }
        // The loop's one call of traceNow, as in reflectedRadiance.
        if (i > 0u || !kShadowRaysWait) traceNow(term);
        if (i == 0u) waiting = term;
        else L += termValue(term, term.blocked);
    }
    return L;
}

#endif
