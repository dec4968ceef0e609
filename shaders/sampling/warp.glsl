// Warps from the unit square [0,1)^2 to the domains that direct illumination samples:
// hemisphere (uniform, cosine, Phong lobe), sphere, cone, disk and triangle. Each warp
// is followed by its density, and the comment names the measure that density is in.
// Everything is in a local frame with +z as the axis; callers rotate with frameToWorld
// (common/math.glsl). Light and BSDF code convert between measures, never this file.
//
// Sources: Nori include/nori/warp.h + src/warp.cpp (names, one density per warp);
// pbrt-v4 src/pbrt/util/sampling.h (SampleUniformCone, SampleUniformTriangle, the
// concentric disk); Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square";
// Heitz 2019, "A Low-Distortion Map Between Triangle and Square".
#ifndef PENUMBRA_WARP_GLSL
#define PENUMBRA_WARP_GLSL

#include "common/math.glsl"

// ---- Helpers ---------------------------------------------------------------------------

// The largest float below 1.
const float ONE_MINUS_EPSILON = 0.99999994;

// Sample reuse (PBR book 3rd ed., section 14.1.6, BSDF::Sample_f; pbrt-v4's
// AliasTable::Sample): a uniform u in [0,1) that chose between two options, the first for
// u < p, stretched back onto [0,1) within the chosen option's share. Given either choice
// the result is uniform again, so it can drive that option's sample in place of a fresh
// number, and where u is stratified the choices and the samples of each option are
// stratified together.
float remapAfterChoice(float u, float p) {
    return min(u < p ? u / p : (u - p) / (1.0 - p), ONE_MINUS_EPSILON);
}

// 1 - cos(theta) of a unit vector about +z, without the cancellation of 1 - v.z near the
// pole: for z > 0, 1 - z = (x^2 + y^2) / (1 + z). Needed to tell whether a direction lies
// in a cone whose 1 - cos(thetaMax) is ~1e-5, below the float spacing of z near 1.
float oneMinusCosTheta(vec3 v) {
    return v.z > 0.0 ? (v.x * v.x + v.y * v.y) / (1.0 + v.z) : 1.0 - v.z;
}

// exp(x) - 1 without cancellation for small |x| (GLSL has no expm1): Taylor series to
// x^4 below 1e-2 (truncation error < x^5/120, i.e. < 1e-10 relative), exp(x) - 1 above.
float expm1Accurate(float x) {
    if (abs(x) < 1e-2) return x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x * (1.0 / 24.0))));
    return exp(x) - 1.0;
}

// log(1 + x) without the absolute error of log() near 1 (GLSL guarantees only ~2^-21
// there, which cos^n with n = 1e4 would amplify to 1e-3 relative): Taylor series to x^5
// below 1e-2 (truncation error < x^6/6), log(1 + x) above.
float log1pAccurate(float x) {
    if (abs(x) < 1e-2) return x * (1.0 - x * (0.5 - x * (1.0 / 3.0 - x * (0.25 - x * 0.2))));
    return log(1.0 + x);
}

// Unit vector at polar angle theta (given as cos and sin) and azimuth phi about +z.
vec3 sphericalDirection(float sinTheta, float cosTheta, float phi) {
    return vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}

// ---- Disk ------------------------------------------------------------------------------

// Concentric map of Shirley & Chiu 1997 (the form of pbrt-v4 SampleUniformDiskConcentric):
// square [0,1)^2 -> unit disk, area-preserving up to a constant, so that strata stay
// compact and neighbours stay neighbours. Uniform on the disk.
vec2 squareToConcentricDisk(vec2 u) {
    vec2 o = 2.0 * u - 1.0;
    if (o.x == 0.0 && o.y == 0.0) return vec2(0.0);
    float r, theta;
    if (abs(o.x) > abs(o.y)) {
        r = o.x;
        theta = (0.25 * PI) * (o.y / o.x);
    } else {
        r = o.y;
        theta = 0.5 * PI - (0.25 * PI) * (o.x / o.y);
    }
    return r * vec2(cos(theta), sin(theta));
}

// Uniform point on the unit disk in the xy plane (concentric map).
vec2 squareToUniformDisk(vec2 u) { return squareToConcentricDisk(u); }
// Density w.r.t. AREA on the unit disk: 1/pi inside, 0 outside (the 1e-6 slack admits
// points on the rim whose cos^2 + sin^2 rounded above 1).
float uniformDiskPdf(vec2 p) { return dot(p, p) <= 1.0 + 1e-6 ? INV_PI : 0.0; }

// ---- Hemisphere ------------------------------------------------------------------------

// Uniform direction on the hemisphere z >= 0 (Nori squareToUniformHemisphere): z = u.x is
// uniform because the area of a zone is proportional to its height (Archimedes).
// sin(theta) from (1 - z)(1 + z): both factors are exact in float, unlike 1 - z^2.
vec3 squareToUniformHemisphere(vec2 u) {
    float z = u.x;
    float r = sqrt(max(0.0, (1.0 - z) * (1.0 + z)));
    return sphericalDirection(r, z, TWO_PI * u.y);
}
// Density w.r.t. SOLID ANGLE: 1/(2 pi) for v.z >= 0, else 0.
float uniformHemispherePdf(vec3 v) { return v.z >= 0.0 ? INV_TWO_PI : 0.0; }

// Cosine-weighted direction on the hemisphere z >= 0 by Malley's method: a uniform point
// on the disk (concentric map, Shirley & Chiu 1997) lifted to the hemisphere; pbrt-v4
// SampleCosineHemisphere, Nori squareToCosineHemisphere. u.x = 0 or u.y = 0 can land on
// the rim z = 0, where the pdf is 0 (chance ~2^-23): callers skip samples with pdf 0.
vec3 squareToCosineHemisphere(vec2 u) {
    vec2 d = squareToConcentricDisk(u);
    float z = sqrt(max(0.0, 1.0 - dot(d, d)));
    return vec3(d, z);
}
// Density w.r.t. SOLID ANGLE: cos(theta)/pi for cos(theta) > 0, else 0.
float cosineHemispherePdf(float cosTheta) { return cosTheta > 0.0 ? cosTheta * INV_PI : 0.0; }

// ---- Phong lobe ------------------------------------------------------------------------

// Direction distributed as cos^n(alpha) about +z, n >= 0 (n = 0: uniform hemisphere).
// The solid-angle density p = (n+1)/(2 pi) cos^n has cos(alpha) with marginal density
// (n+1) mu^n on [0,1], CDF mu^(n+1), hence by inversion cos(alpha) = (1 - u.x)^(1/(n+1)).
// NOTE the lecture's (n+2)/(2 pi) cos^n is the Phong BRDF normalisation (it makes
// integral f cos(theta) d(omega) = 1); its inversion with exponent 1/(n+2) samples the
// density (n+2)/(2 pi) cos^(n+1), i.e. the lobe times the cosine, not this one.
// 1 - cos(alpha) = -expm1(log1p(-u.x) / (n+1)) stays accurate for n = 1e4, where
// cos(alpha) is within 1e-4 of 1 (u.x < 1, so the log is finite).
vec3 squareToPhongLobe(vec2 u, float n) {
    float logCos = log1pAccurate(-u.x) / (n + 1.0);  // log(cos alpha) <= 0
    float oneMinusCos = -expm1Accurate(logCos);
    float cosAlpha = 1.0 - oneMinusCos;
    float sinAlpha = sqrt(max(0.0, oneMinusCos * (2.0 - oneMinusCos)));
    return sphericalDirection(sinAlpha, cosAlpha, TWO_PI * u.y);
}
// Density w.r.t. SOLID ANGLE: (n+1)/(2 pi) cos^n(alpha) for cos(alpha) > 0, else 0.
// cos^n as exp(n log cos): no pow(0, 0) (undefined in GLSL) at n = 0, and for large n it
// underflows to 0 instead of producing NaN or inf. log cos = log1p(-(1 - cos)), where
// 1 - cos is exact in float for cos >= 1/2, keeps cos^n good to ~1e-6 at n = 1e4.
float phongLobePdf(float cosAlpha, float n) {
    if (cosAlpha <= 0.0) return 0.0;
    return (n + 1.0) * INV_TWO_PI * exp(n * log1pAccurate(-(1.0 - cosAlpha)));
}

// ---- Sphere ----------------------------------------------------------------------------

// Uniform direction on the unit sphere (Nori squareToUniformSphere): z = 1 - 2 u.x is
// uniform in [-1, 1]; sin(theta) = 2 sqrt(u.x (1 - u.x)) with no cancellation.
vec3 squareToUniformSphere(vec2 u) {
    float z = 1.0 - 2.0 * u.x;
    float r = 2.0 * sqrt(max(0.0, u.x * (1.0 - u.x)));
    return sphericalDirection(r, z, TWO_PI * u.y);
}
// Density w.r.t. SOLID ANGLE: 1/(4 pi) everywhere.
float uniformSpherePdf() { return INV_FOUR_PI; }

// ---- Cone ------------------------------------------------------------------------------

// Uniform direction in the cone {theta <= thetaMax} about +z, given 1 - cos(thetaMax) in
// (0, 2]. The cone's solid angle is 2 pi (1 - cos(thetaMax)) and 1 - cos(theta) is uniform
// in [0, 1 - cos(thetaMax)] (pbrt-v4 SampleUniformCone). Working in 1 - cos keeps tiny
// cones exact: a sphere light of radius r at distance d has 1 - cos(thetaMax) ~ r^2/(2d^2),
// which cos(thetaMax) in float cannot hold once it falls below ~1e-7 (pbrt-v4
// Sphere::Sample switches to the same form for small angles).
vec3 squareToUniformConeOneMinusCos(vec2 u, float oneMinusCosThetaMax) {
    float oneMinusCos = u.x * oneMinusCosThetaMax;
    float cosTheta = 1.0 - oneMinusCos;
    float sinTheta = sqrt(max(0.0, oneMinusCos * (2.0 - oneMinusCos)));
    return sphericalDirection(sinTheta, cosTheta, TWO_PI * u.y);
}
// The same cone given cos(thetaMax) in [-1, 1); prefer the form above for narrow cones.
vec3 squareToUniformCone(vec2 u, float cosThetaMax) {
    return squareToUniformConeOneMinusCos(u, 1.0 - cosThetaMax);
}
// Density w.r.t. SOLID ANGLE inside the cone: 1 / (2 pi (1 - cos(thetaMax))); 0 outside,
// which uniformConeContains tells.
float uniformConePdfOneMinusCos(float oneMinusCosThetaMax) { return 1.0 / (TWO_PI * oneMinusCosThetaMax); }
float uniformConePdf(float cosThetaMax) { return uniformConePdfOneMinusCos(1.0 - cosThetaMax); }
// Whether unit v lies in the cone; the relative slack 1e-5 admits samples on the rim whose
// components rounded outward (1 - cos from float x, y, z is good to a few 1e-7).
bool uniformConeContains(vec3 v, float oneMinusCosThetaMax) {
    return oneMinusCosTheta(v) <= oneMinusCosThetaMax * (1.0 + 1e-5);
}

// ---- Triangle --------------------------------------------------------------------------

// Uniform point on a triangle as barycentrics (b0, b1, b2), b0 + b1 + b2 = 1: the
// low-distortion map of Heitz 2019 as in pbrt-v4 SampleUniformTriangle. The point is
// b0 p0 + b1 p1 + b2 p2 for any triangle (p0, p1, p2).
vec3 squareToUniformTriangle(vec2 u) {
    float b0, b1;
    if (u.x < u.y) {
        b0 = 0.5 * u.x;
        b1 = u.y - b0;
    } else {
        b1 = 0.5 * u.y;
        b0 = u.x - b1;
    }
    return vec3(b0, b1, 1.0 - b0 - b1);
}
// Density w.r.t. AREA on a triangle of the given area: 1/area (inside the triangle).
float uniformTrianglePdf(float area) { return 1.0 / area; }

#endif
