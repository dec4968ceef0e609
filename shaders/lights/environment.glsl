// Environment light (SCENE_FORMAT.md `environment`): radiance arriving from every direction
// at infinity, seen by rays that leave the scene. A constant sky is sampled cosine-weighted
// about the shading normal, in proportion to the integrand's cosine (PBR book 3rd ed.,
// 13.6.3, Malley's method); a map by its texels (lights/environment_map.glsl).
#ifndef PENUMBRA_LIGHTS_ENVIRONMENT_GLSL
#define PENUMBRA_LIGHTS_ENVIRONMENT_GLSL

#include "common/specialization.glsl"
#include "lights/light_sample.glsl"
#include "lights/environment_map.glsl"
#include "sampling/warp.glsl"

// False at compile time in scenes without a map (FEATURE_ENVIRONMENT_MAP).
bool environmentHasMap(Light light) { return hasEnvironmentMap() && (light.flags & LIGHT_ENVIRONMENT_MAP) != 0u; }

// Radiance arriving from direction wi (pointing away from the scene).
vec3 environmentRadiance(Light light, vec3 wi) {
    if (environmentHasMap(light)) return environmentMapRadiance(light, wi);
    return light.emission;
}

bool sampleEnvironmentLight(Light light, vec3 n, vec3 u, inout LightSample ls) {
    if (environmentHasMap(light)) return sampleEnvironmentMap(light, u, ls);
    vec3 local = squareToCosineHemisphere(u.xy);
    ls.wi = frameToWorld(local, n);
    ls.pdf = cosineHemispherePdf(local.z);
    ls.radiance = environmentRadiance(light, ls.wi);
    return ls.pdf > 0.0;
}

// Solid-angle density of wi under sampleEnvironmentLight from a point with normal n.
float environmentPdf(Light light, vec3 n, vec3 wi) {
    if (environmentHasMap(light)) return environmentMapPdf(light, wi);
    return max(dot(wi, n), 0.0) * INV_PI;
}

#endif
