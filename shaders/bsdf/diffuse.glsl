// The `diffuse` BRDF of SCENE_FORMAT.md, f = kd / pi (kd = the albedo), with its cosine-
// weighted sampling: value, pdf and sample side by side. Directions are unit world-space
// vectors pointing away from the surface; bsdf/bsdf.glsl has already checked that wo and
// wi lie above the surface before eval and pdf are called.
#ifndef PENUMBRA_BSDF_DIFFUSE_GLSL
#define PENUMBRA_BSDF_DIFFUSE_GLSL

#include "shared/types.h"
#include "common/math.glsl"
#include "sampling/warp.glsl"

// Lambert: a constant kd / pi reflects kd of the irradiance (lecture, "Diffuse BRDF").
vec3 diffuseEval(Material m) { return m.kd * INV_PI; }

// Cosine-weighted density cos(theta) / pi (lecture, "Cosine-weighted sampling").
float diffusePdf(float cosThetaI) { return cosThetaI * INV_PI; }

// Malley's method: a uniform disk point lifted onto the hemisphere about n.
vec3 diffuseSample(vec3 n, vec2 u) { return frameToWorld(squareToCosineHemisphere(u), n); }

#endif
