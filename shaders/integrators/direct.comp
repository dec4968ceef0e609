// One bounce of direct illumination (SCENE_FORMAT.md "direct"; lecture, "Importance
// Sampling Incident Radiance" onwards): emitted radiance seen by the camera ray, plus light
// reflected once from every light, estimated with one of four strategies:
//   light    N1 light samples              (f Le cos / (P(l) p_l))
//   bsdf     N2 BRDF samples               (f Le cos / p_f), counted when they hit an emitter
//   mis      N1 light + N2 BRDF samples weighted by the balance or power heuristic
//   mixture  N1 + N2 samples from 0.5 p_light + 0.5 p_f (lecture, "Sample from Average PDF")
//   ris      N1 draws, each one of M light + N2 BRDF candidates resampled (integrators/ris.glsl)
// Delta lights cannot be hit: every strategy samples them explicitly (light and mis through
// the full selection table; bsdf and mixture with one delta-only draw per sample).
// The strategy, heuristic, N1, N2 and sphere, quad and triangle sampling are specialization constants
// (common/specialization.glsl): each combination is its own compiled kernel.
// cmake/EmbedShaders.cmake also compiles it as direct_inline<N>, with small scenes'
// primitives inline instead of the BVH (geometry/inline_geometry.glsl).
#version 450
#extension GL_GOOGLE_include_directive : require

// The "_address" variant traces each sample's camera ray together with the previous
// sample's shadow rays (addPixelSamples, at the end): it brings its own sample loop.
#if defined(PENUMBRA_NODE_ADDRESS) && !defined(PENUMBRA_INLINE_GEOMETRY)
#define PENUMBRA_TRACE_PAIRS
#define PENUMBRA_KERNEL_SAMPLE_LOOP
const bool kShadowRaysWait = true;
#else
const bool kShadowRaysWait = false;
#endif

#include "integrators/kernel_common.glsl"
#include "common/specialization.glsl"
// Before the traversal: its triangle hits run the alpha test (textures/alpha_mask.glsl).
#include "textures/alpha_mask.glsl"
#include "geometry/bvh.glsl"
#include "geometry/surface.glsl"
#include "sampling/warp.glsl"
// Before the lights: mesh lights read emission textures (lights/mesh.glsl).
#include "textures/textures.glsl"
#include "lights/lights.glsl"
#include "bsdf/bsdf.glsl"
#include "integrators/mis.glsl"
#include "integrators/emitter_first.glsl"
#include "integrators/light_selection_bvh.glsl"

#include "bsdf/materials.glsl"
#include "textures/textures.glsl"
#include "textures/normal_map.glsl"
#include "integrators/aov.glsl"

// How area lights are sampled, for sampleLight and lightPdf alike.
LightSamplingModes lightModes() {
    return LightSamplingModes(kSphereSampling, kQuadSampling, kTriangleSampling, SPHERICAL_MIN_SOLID_ANGLE,
                              SPHERICAL_MIN_ELEVATION_SINE);
}

// The shading point, with normals turned to the viewer's side (two-sided materials).
struct Shading {
    vec3 x;       // position
    // x offset off the surface for rays leaving on the viewer's side. Light samples and
    // their densities are taken from here, not from x, so that each shadow ray runs
    // exactly along the sampled segment: sampling from x and tracing from the offset
    // origin shifts the ray sideways, and near a small sphere light's silhouette the
    // shifted ray enters the sphere before the sampled point (measured: 0.05% of the
    // light lost for a sphere of radius 0.05 at distance 3).
    vec3 origin;
    vec3 ng;      // geometric normal
    vec3 ns;      // shading normal
    vec3 wo;      // toward the viewer
    Material m;
    // The triangle or quad x lies on (NO_HIT for a sphere), which no ray from `origin` that
    // counts can meet: such a ray leaves on the side of ng (cosineWeighted), and `origin`
    // lies off the primitive's plane on that side, so the plane is behind the ray. Its test
    // beside the tree is left out of those rays (geometry/bvh.glsl, traverse).
    uint flatPrimitive;
};

// A term of the estimate, and the shadow ray that decides whether it counts: the term is
// `value` where nothing blocks the ray, 0 where something does. `ray.traced` false: the
// term is 0, with no ray to trace. For a light sample the ray runs from the shading point's
// offset origin toward the sampled point; for a BRDF sample that found an emitter first, it
// is the query whether anything hides that emitter (emitter_first.glsl). Sampling and
// tracing are apart so that the kernel can trace a sample's first such rays later, together
// with the next sample's camera ray (addPixelSamples).
struct ShadowedTerm {
    vec3 value;
    AnyHitRay ray;  // its `ignore`: primitives that cannot block it (traverse's; NO_HIT: none)
    bool blocked;   // what traceNow found
};

ShadowedTerm noShadowedTerm() { return ShadowedTerm(vec3(0.0), noAnyHitRay(), false); }

// Traces the term's shadow ray at once.
void traceNow(inout ShadowedTerm term) {
    term.blocked = term.ray.traced && traceAnyIgnoring(term.ray.origin, term.ray.dir, term.ray.tMax, term.ray.ignore);
}

// The term's share of the estimate: its value where traced and unblocked, else 0.
vec3 termValue(ShadowedTerm term, bool blocked) { return term.ray.traced && !blocked ? term.value : vec3(0.0); }

// f * cos for a direction whose BRDF value is f, zero below either normal.
vec3 cosineWeighted(Shading s, vec3 wi, vec3 f) {
    float cosI = dot(wi, s.ns);
    if (cosI <= 0.0 || dot(wi, s.ng) <= 0.0) return vec3(0.0);
    return f * cosI;
}

// How a one-sample estimate is weighted against the other technique's samples.
const uint WEIGHT_NONE = 0u;     // its own density alone
const uint WEIGHT_MIS = 1u;      // MIS weight against the other technique's samples (nLight, nBsdf)
const uint WEIGHT_MIXTURE = 2u;  // the mixture density 0.5 p_light + 0.5 p_f (lecture, "Sample from Average PDF")

// A light from the selection table [offset, offset + count), `pmf` its probability, and
// the three numbers that sample it. The choice and the first number share a number of one
// pair (lights.glsl, selectLight): where the sampler stratifies that pair, the
// lights each pixel's samples go to and the points on each light are stratified together,
// as Mitsuba's emitter sampling and pbrt-v4's light samplers reuse the selection number.
uint drawLight(uint offset, uint count, inout Rng rng, out float pmf, out vec3 u) {
    uvec2 bits = rand2Bits(rng);
    float rest;
    uint index = selectLight(offset, count, bits.x, pmf, rest);
    u = vec3(rest, bitsToUnit(bits.y), rand1(rng));
    return index;
}

// A light from the full selection, for the light and mis strategies: drawLight from the
// table [0, lightCount), or under light selection "bvh" the tree's choice at s
// (integrators/light_selection_bvh.glsl), which may be one triangle of a mesh light
// (`triangle`, else NO_HIT). The bvh's light sample gets numbers of its own: the descent
// rescales its number at every level and leaves too few bits of it (pbrt-v4 also draws
// the choice and the sample apart).
uint drawAnyLight(Shading s, inout Rng rng, out float pmf, out vec3 u, out uint triangle) {
    triangle = NO_HIT;
    if (!lightBvhSelection()) return drawLight(0u, params.lightCount, rng, pmf, u);
    uvec2 bits = rand2Bits(rng);
    uint index = drawLightBvh(s.origin, s.ns, bits.x, triangle, pmf);
    // One pair for the light's 2D sample and the choice's other coordinate for the third:
    // two pairs, as the power selection draws (each Sobol' pair costs a hash and a
    // scrambled point). One Owen-scrambled point is uniform on the square, so its two
    // coordinates are independent for the sample.
    vec2 v = rand2(rng);
    u = vec3(v, bitsToUnit(bits.y));
    return index;
}

// The shadow ray of light sample `ls` of light `index` at s: from the offset origin toward
// the sampled point.
AnyHitRay lightShadowRay(Shading s, uint index, LightSample ls) {
    // The shadow ray stops just short of the sampled point, so that the light's own surface
    // does not count as an occluder.
    float tMax = ls.dist == FLOAT_MAX ? FLOAT_MAX : ls.dist * (1.0 - 1e-4);
    // A quad light cannot block a ray toward a point on itself: the ray meets its plane once,
    // there, beyond tMax. Neither can the flat primitive under x (Shading.flatPrimitive).
    // Leaving their tests out changes no image: each would find nothing.
    Light light = loadLight(index);
    uvec2 ignore = uvec2(lightIs(light, LIGHT_QUAD) ? light.first : NO_HIT, s.flatPrimitive);
    return AnyHitRay(s.origin, ls.wi, tMax, true, ignore);
}

// One sample, from the numbers u, of light `index` (of its triangle `triangle` alone, unless
// NO_HIT) drawn with probability `pmf` (drawLight, drawAnyLight), weighted against N2 BRDF
// samples (WEIGHT_MIS) or by the mixture density: its term, with the shadow ray still to
// trace. quadSolidAnglePdf receives the sample's LightSample.quadSolidAnglePdf when the
// light was sampled.
ShadowedTerm lightSampleTerm(Shading s, uint index, uint triangle, float pmf, vec3 u, uint weighting, float nLight,
                             float nBsdf, inout float quadSolidAnglePdf) {
    ShadowedTerm term = noShadowedTerm();
    if (!(pmf > 0.0)) return term;
    LightSample ls;
    bool sampled = lightBvhSelection() ? sampleLightPart(index, triangle, s.origin, s.ns, u, lightModes(), ls)
                                       : sampleLight(index, s.origin, s.ns, u, lightModes(), ls);
    quadSolidAnglePdf = ls.quadSolidAnglePdf;
    if (!sampled) return term;
    BsdfValue b = bsdfEvalPdf(s.m, s.ns, s.wo, ls.wi);
    vec3 fc = cosineWeighted(s, ls.wi, b.f);
    if (fc == vec3(0.0)) return term;
    term.ray = lightShadowRay(s, index, ls);
    if (ls.isDelta) {
        term.value = fc * ls.radiance / pmf;
        return term;
    }
    float pLight = pmf * ls.pdf;
    float density = pLight;
    float weight = 1.0;
    if (weighting == WEIGHT_MIS) {
        weight = misWeight(nLight * pLight, nBsdf * b.pdf, kHeuristic);
    } else if (weighting == WEIGHT_MIXTURE) {
        density = 0.5 * pLight + 0.5 * b.pdf;
    }
    term.value = fc * ls.radiance * weight / density;
    return term;
}

// lightSampleTerm with its shadow ray traced now.
vec3 lightSampleEstimate(Shading s, uint index, float pmf, vec3 u, uint weighting, float nLight, float nBsdf,
                         inout float quadSolidAnglePdf) {
    ShadowedTerm term = lightSampleTerm(s, index, NO_HIT, pmf, u, weighting, nLight, nBsdf, quadSolidAnglePdf);
    traceNow(term);
    return termValue(term, term.blocked);
}

// Emitted radiance reaching x along wi (first hit, or the environment when nothing is
// hit), and the light-selection-times-light density of that direction, with `selection`
// turning Light::selectionProb into the probability in the table actually sampled, or with
// `bvh` the probability of light selection "bvh" at x, replayed (light_selection_bvh.glsl).
// With the emitter-first path (integrators/emitter_first.glsl; only in scenes without an
// environment light) the hit is the nearest emitter, checked for occluders once it is known
// to emit toward x: at once, or, with `waits`, by the caller, who receives that query in
// `hidden` (otherwise none). `quad`: the light's quad density at x where a light sample
// knows it.
vec3 incidentEmission(Shading s, vec3 wi, float selectionScale, bool bvh, KnownQuadDensity quad, bool waits,
                      out float pLight, out AnyHitRay hidden) {
    pLight = 0.0;
    hidden = noAnyHitRay();
    Hit hit;
    if (!traceForEmission(s.origin, wi, hit)) {
        // The environment's own density, not lightPdf's dispatch over every kind: llvmpipe
        // would run the area lights' densities here too, for a light known to be none.
        if (!hasLight(LIGHT_ENVIRONMENT) || params.environmentLight == NO_LIGHT) return vec3(0.0);
        Light env = loadLight(params.environmentLight);
        float selection = bvh ? lightBvhInfinitePmf() : env.selectionProb * selectionScale;
        pLight = selection * environmentPdf(env, s.ns, wi);
        return environmentRadiance(env, wi);
    }
    SurfacePoint y = surfaceAt(hit, s.origin, wi);
    if (y.light == NO_LIGHT) return vec3(0.0);
    Light light = loadLight(y.light);
    vec3 Le = emittedRadiance(light, y.geometricNormal, wi) * emissionTexture(y.material, y.uv);
    if (Le == vec3(0.0)) return vec3(0.0);
    if (waits && emitterFirst()) hidden = emitterHiddenRay(s.origin, wi, hit, s.flatPrimitive);
    else if (emitterHidden(s.origin, wi, hit, s.flatPrimitive)) return vec3(0.0);
    if (bvh) {
        pLight = lightBvhPrimitivePmf(s.origin, s.ns, hit.primitive) *
                 lightPartPdf(y.light, s.origin, s.ns, wi, y.position, y.geometricNormal, hit.t, hit.primitive,
                              lightModes(), quad);
        return Le;
    }
    pLight = light.selectionProb * selectionScale *
             lightPdf(y.light, s.origin, s.ns, wi, y.position, y.geometricNormal, hit.t, hit.primitive, lightModes(), quad);
    return Le;
}

// One BRDF sample, weighted against N1 light samples from the full table (WEIGHT_MIS) or
// by the mixture density with the continuous-light table (WEIGHT_MIXTURE). With `waits`,
// a sample whose emitter is still to be checked for occluders (incidentEmission) returns
// 0 and leaves its value and that query in `waiting`; otherwise `waiting` holds none.
vec3 bsdfSampleEstimate(Shading s, uint weighting, float nLight, float nBsdf, KnownQuadDensity quad, bool waits,
                        inout Rng rng, out ShadowedTerm waiting) {
    waiting = noShadowedTerm();
    vec3 wi;
    BsdfValue b;
    if (!bsdfSample(s.m, s.ns, s.wo, rand2(rng), wi, b)) return vec3(0.0);
    vec3 fc = cosineWeighted(s, wi, b.f);
    if (fc == vec3(0.0)) return vec3(0.0);
    float pBsdf = b.pdf;
    float pLight;
    float scale = weighting == WEIGHT_MIXTURE ? params.continuousScale : 1.0;
    // MIS weighs against the light samples' selection: the tree's under "bvh".
    bool bvh = lightBvhSelection() && weighting == WEIGHT_MIS;
    vec3 Le = incidentEmission(s, wi, scale, bvh, quad, waits, pLight, waiting.ray);
    if (Le == vec3(0.0)) return vec3(0.0);
    float density = pBsdf;
    float weight = 1.0;
    if (weighting == WEIGHT_MIS) weight = misWeight(nBsdf * pBsdf, nLight * pLight, kHeuristic);
    else if (weighting == WEIGHT_MIXTURE) density = 0.5 * pLight + 0.5 * pBsdf;
    vec3 value = fc * Le * weight / density;
    if (!waiting.ray.traced) return value;
    waiting.value = value;
    return vec3(0.0);
}

// One draw from the delta-only table: the explicit estimate of point and directional
// lights for strategies whose other samples cannot find them.
vec3 deltaLightEstimate(Shading s, inout Rng rng) {
    if (params.deltaCount == 0u) return vec3(0.0);
    float pmf;
    vec3 u;
    uint index = drawLight(params.deltaTableOffset, params.deltaCount, rng, pmf, u);
    float unused;
    return lightSampleEstimate(s, index, pmf, u, WEIGHT_NONE, 0.0, 0.0, unused);
}

// Strategy "ris": uses Shading, drawAnyLight, lightShadowRay and incidentEmission above.
#include "integrators/ris.glsl"

// The terms of a sample that reflectedRadiance leaves apart: the first light sample's (light
// and mis strategies) and, with mis, the last BRDF sample's, each with its shadow ray traced
// or, in the kernel that traces them with the next sample's camera ray, not yet (a BRDF
// sample's only where its emitter was found first, emitter_first.glsl); none otherwise.
struct WaitingTerms {
    ShadowedTerm light;
    ShadowedTerm bsdf;
};

WaitingTerms noWaitingTerms() { return WaitingTerms(noShadowedTerm(), noShadowedTerm()); }

// Light reflected at s toward the viewer, apart from the terms it leaves in `waiting`.
vec3 reflectedRadiance(Shading s, inout Rng rng, out WaitingTerms waiting) {
    uint n1 = kLightSamples, n2 = kBsdfSamples;
    vec3 L = vec3(0.0);
    waiting = noWaitingTerms();
    // With one light in the scene, MIS draws its light samples from x before its BRDF
    // samples, and any BRDF-sampled ray that finds a light finds that one: its quad density
    // at x is what the light samples computed (the same for every one of them). It stays 0
    // (the area density) only where the light's selection probability is 0, and then the
    // MIS weight multiplies it by that 0.
    float quadSolidAnglePdf = 0.0;
    if (kStrategy == STRATEGY_LIGHT || kStrategy == STRATEGY_MIS) {
        uint weighting = kStrategy == STRATEGY_MIS ? WEIGHT_MIS : WEIGHT_NONE;
        for (uint i = 0u; i < n1; ++i) {
            float pmf;
            vec3 u;
            uint triangle;
            uint index = drawAnyLight(s, rng, pmf, u, triangle);
            ShadowedTerm term =
                lightSampleTerm(s, index, triangle, pmf, u, weighting, float(n1), float(n2), quadSolidAnglePdf);
            term.value /= float(n1);
            // At the loop's one call of traceNow, so that the kernel holds one copy of the
            // traversal (with inline geometry, of every primitive's test) for all of them.
            if (i > 0u || !kShadowRaysWait) traceNow(term);
            if (i == 0u) waiting.light = term;
            else L += termValue(term, term.blocked);
        }
    }
    if (kStrategy == STRATEGY_BSDF || kStrategy == STRATEGY_MIS) {
        uint weighting = kStrategy == STRATEGY_MIS ? WEIGHT_MIS : WEIGHT_NONE;
        float nLight = kStrategy == STRATEGY_MIS ? float(n1) : 0.0;
        KnownQuadDensity quad = KnownQuadDensity(kStrategy == STRATEGY_MIS && n1 > 0u && hasSingleLight(), quadSolidAnglePdf);
        for (uint i = 0u; i < n2; ++i) {
            // The last BRDF sample of mis with light samples is the last term added here, so
            // it may wait: finishedSample adds it in the same order.
            bool waits = kShadowRaysWait && kStrategy == STRATEGY_MIS && n1 > 0u && i == n2 - 1u;
            ShadowedTerm term;
            L += bsdfSampleEstimate(s, weighting, nLight, float(n2), quad, waits, rng, term) / float(n2);
            if (waits) {
                term.value /= float(n2);
                waiting.bsdf = term;
            }
            // Without light samples, delta lights get their own explicit draw.
            if (nLight == 0.0) L += deltaLightEstimate(s, rng) / float(n2);
        }
    }
    if (kStrategy == STRATEGY_MIXTURE) {
        uint n = n1 + n2;
        for (uint i = 0u; i < n; ++i) {
            if (rand1(rng) < 0.5) {
                if (params.continuousCount > 0u) {
                    float pmf;
                    vec3 u;
                    uint index = drawLight(params.continuousTableOffset, params.continuousCount, rng, pmf, u);
                    float unused;
                    L += lightSampleEstimate(s, index, pmf, u, WEIGHT_MIXTURE, 0.0, 0.0, unused) / float(n);
                }
            } else {
                ShadowedTerm none;
                L += bsdfSampleEstimate(s, WEIGHT_MIXTURE, 0.0, 0.0, unknownQuadDensity(), false, rng, none) / float(n);
            }
            L += deltaLightEstimate(s, rng) / float(n);
        }
    }
    if (kStrategy == STRATEGY_RIS) L += risReflectedRadiance(s, rng, waiting.light);
    return L;
}

// A sample's radiance in parts: emitted + reflected, and the terms whose shadow rays may
// still wait (reflectedRadiance). finishedSample adds them up.
struct PartialSample {
    vec3 emitted;
    vec3 reflected;
    WaitingTerms waiting;
    AovFirstHit aov;  // for the AOV layers (integrators/aov.glsl); unused where kAovs is 0
};

PartialSample noPartialSample() { return PartialSample(vec3(0.0), vec3(0.0), noWaitingTerms(), aovMiss()); }

// The sample that the camera ray (origin, dir) found. `rng` goes on from the camera ray's
// numbers.
PartialSample partialSample(bool found, Hit hit, vec3 origin, vec3 dir, inout Rng rng) {
    PartialSample p = noPartialSample();
    if (!found) {
        if (params.environmentLight != NO_LIGHT)
            p.emitted = environmentRadiance(loadLight(params.environmentLight), dir);
        return p;
    }
    SurfacePoint sp = surfaceAt(hit, origin, dir);
    sp.shadingNormal = normalMapped(sp);  // the BRDF, its sampling and the normal AOV see it
    if (sp.light != NO_LIGHT)
        p.emitted = emittedRadiance(loadLight(sp.light), sp.geometricNormal, dir) * emissionTexture(sp.material, sp.uv);

    Shading s;
    s.x = sp.position;
    s.wo = -dir;
    viewerSideNormals(sp, s.wo, s.ng, s.ns);
    s.origin = offsetRayOrigin(s.x, s.ng);
    s.flatPrimitive = sp.primitiveType == PRIM_SPHERE ? NO_HIT : hit.primitive;
    s.m = applyTextures(loadMaterial(sp.material), sp.material, sp.uv);
    if (kAovs != 0u) p.aov = aovFirstHit(sp, hit.t, s.ns, s.m);
    p.reflected = reflectedRadiance(s, rng, p.waiting);
    return p;
}

// The sample's radiance, given whether the waiting terms' shadow rays are blocked: the BRDF
// term joins the reflected light where it was the last added, and the light term the sum
// last. Both ways of tracing those rays end here, so they give the same sums bit for bit.
vec3 finishedSample(PartialSample p, bool lightBlocked, bool bsdfBlocked) {
    vec3 reflected = p.reflected + termValue(p.waiting.bsdf, bsdfBlocked);
    vec3 rest = p.emitted + reflected;
    return p.waiting.light.ray.traced && !lightBlocked ? rest + p.waiting.light.value : rest;
}

#ifdef PENUMBRA_TRACE_PAIRS
// A pixel's samples, software-pipelined (kernel_common.glsl, addPixelSamples, says what the
// loop keeps): iteration k traces sample k's camera ray together with sample k - 1's
// waiting shadow rays (geometry/bvh.glsl, tracePair), then finishes sample k - 1 and shades
// sample k up to its own waiting rays. The first iteration has no shadow ray to trace and the
// last no camera ray. Sample k - 1 is added before sample k is shaded, in sample order.
void addPixelSamples(uvec2 pixel) {
    uint index = pixel.y * params.width + pixel.x;
    AccumSum sum = accum[index];
    vec3 compensation = accumCompensation[index].compensation;
    AovSums aovs = loadAovSums(index);
    uint first = firstSampleOf(sum), end = pass.sampleIndex + pass.sampleCount;
    uint count = end > first ? end - first : 0u;
    PartialSample last = noPartialSample();
    for (uint k = 0u; k <= count; ++k) {
        bool camera = k < count;
        Rng rng = pixelRng(pixel, first + k);
        vec3 origin, dir;
        cameraRay(pixel, rand2(rng), origin, dir);
        Hit hit;
        bool lightBlocked, bsdfBlocked;
        // Only emitter-first BRDF samples wait (bsdfSampleEstimate): elsewhere none is
        // passed, a constant, so that the compiler leaves tracePair's third ray out.
        AnyHitRay bsdfRay = emitterFirst() ? last.waiting.bsdf.ray : noAnyHitRay();
        bool found = tracePair(origin, dir, FLOAT_MAX, camera, cameraRayIgnores(), hit, last.waiting.light.ray, bsdfRay,
                               lightBlocked, bsdfBlocked);
        // Sample k - 1 is whole where no loop has been cut yet (kernel_common.glsl).
        if (loopsWereCut()) break;
        if (k > 0u) {
            vec3 radiance = finishedSample(last, lightBlocked, bsdfBlocked);
            addSample(sum, compensation, radiance);
            addAovSample(aovs, pixel, first + k - 1u, radiance, last.aov);
        }
        if (camera) last = partialSample(found, hit, origin, dir, rng);
    }
    accum[index] = sum;
    accumCompensation[index].compensation = compensation;
    storeAovSums(index, aovs);
}
#else
vec3 pixelSample(uvec2 pixel, uint sampleIndex, out AovFirstHit aov) {
    Rng rng = pixelRng(pixel, sampleIndex);
    vec3 origin, dir;
    cameraRay(pixel, rand2(rng), origin, dir);
    Hit hit;
    bool found = traceClosestIgnoring(origin, dir, FLOAT_MAX, cameraRayIgnores(), hit);
    PartialSample p = partialSample(found, hit, origin, dir, rng);
    aov = p.aov;
    return finishedSample(p, p.waiting.light.blocked, p.waiting.bsdf.blocked);
}
#endif
