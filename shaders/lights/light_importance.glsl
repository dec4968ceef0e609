// The importance of a cluster of lights at a shading point: a bound on what the lights in a
// box, with a cone of normals and an emission angle, can contribute there (pbrt-v4
// CompactLightBounds::Importance; PBR book 4th ed. section 12.6.3; Conty Estevez and Kulla
// 2018). It takes the terms that do not depend on the point (shared/light_bvh.h,
// LightImportanceTerms): the light BVH derives them from a node at every shading point
// (lights/light_bvh.glsl), the flat form of small trees gets them from the host as
// constants (lights/light_flat.glsl). Mirrors host/render/light_bvh.cpp's lightImportance
// operation for operation; its comments say why each step is as it is.
#ifndef PENUMBRA_LIGHT_IMPORTANCE_GLSL
#define PENUMBRA_LIGHT_IMPORTANCE_GLSL

#include "shared/light_bvh.h"

float lightBvhSafeSqrt(float x) { return sqrt(max(x, 0.0)); }

// cos(max(0, a - b)) and sin(max(0, a - b)) from the sines and cosines of a and b.
float lightBvhCosSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 1.0 : cosA * cosB + sinA * sinB;
}
float lightBvhSinSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 0.0 : sinA * cosB - cosA * sinB;
}

// Importance of the lights of `t` at p with shading normal n (n = 0: no surface).
float lightImportance(LightImportanceTerms t, vec3 p, vec3 n) {
    vec3 toP = p - t.center;
    float d2Raw = dot(toP, toP);
    // Inside the box's bounding sphere: no angular bound.
    if (d2Raw <= t.halfDiagonal2) return t.power / max(t.halfDiagonal2, 1e-20);
    float d2 = max(d2Raw, t.halfDiagonal2);
    vec3 wi = toP / sqrt(d2Raw);
    // The cone of directions from p that the box subtends (pbrt-v4 BoundSubtendedDirections).
    float cosThetaB = lightBvhSafeSqrt(1.0 - t.halfDiagonal2 / d2Raw);
    float sinThetaB = lightBvhSafeSqrt(1.0 - cosThetaB * cosThetaB);
    // The smallest angle between a normal in the cone and a direction toward p from the box.
    // Normals in every direction (points, spheres): the general form below gives exactly 1,
    // which a constant cone (lights/light_flat.glsl) then needs none of.
    float cosThetaP = 1.0;
    if (t.cosThetaO > -1.0) {
        float cosThetaW = dot(t.axis, wi);
        if (t.twoSided != 0u) cosThetaW = abs(cosThetaW);
        float sinThetaW = lightBvhSafeSqrt(1.0 - cosThetaW * cosThetaW);
        float cosThetaX = lightBvhCosSubClamped(sinThetaW, cosThetaW, t.sinThetaO, t.cosThetaO);
        float sinThetaX = lightBvhSinSubClamped(sinThetaW, cosThetaW, t.sinThetaO, t.cosThetaO);
        cosThetaP = lightBvhCosSubClamped(sinThetaX, cosThetaX, sinThetaB, cosThetaB);
    }
    if (cosThetaP <= t.cosThetaE) return 0.0;
    float importance = t.power * cosThetaP / d2;
    if (n != vec3(0.0)) {
        // The shading normal's hemisphere: the smallest angle between n and a direction to the box.
        float cosThetaI = abs(dot(wi, n));
        float sinThetaI = lightBvhSafeSqrt(1.0 - cosThetaI * cosThetaI);
        importance *= lightBvhCosSubClamped(sinThetaI, cosThetaI, sinThetaB, cosThetaB);
    }
    return max(importance, 0.0);
}

#endif
