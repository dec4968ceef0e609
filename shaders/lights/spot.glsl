// Spot light (SCENE_FORMAT.md `spot`; glTF KHR_lights_punctual `spot`): intensity I s^2 toward
// w, s = clamp((cos t - cos outer) / (cos inner - cos outer), 0, 1), t the angle between w and
// the axis (the glTF extension's falloff). A delta light like the point light: one direction,
// "pdf" 1, never hit, density 0 for any other strategy's direction.
#ifndef PENUMBRA_LIGHTS_SPOT_GLSL
#define PENUMBRA_LIGHTS_SPOT_GLSL

#include "lights/light_sample.glsl"

// The unit axis from the octahedral coordinates in Light::first/count (shared/types.h;
// Cigolle et al. 2014, "A Survey of Efficient Representations for Independent Unit
// Vectors", JCGT 3(2), listing 1).
vec3 spotAxis(Light light) {
    vec2 e = vec2(uintBitsToFloat(light.first), uintBitsToFloat(light.count));
    vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) v.xy = (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
    return normalize(v);
}

// The glTF falloff s^2 for a unit direction of travel `travel` away from the light.
float spotFalloff(Light light, vec3 travel) {
    float cosOuter = light.area;
    float cosInner = uintBitsToFloat(light.flags);
    float s = clamp((dot(travel, spotAxis(light)) - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
    return s * s;
}

// The direction toward the light from x and I s^2 / d^2. Outside the cone it carries nothing.
bool sampleSpotLight(Light light, vec3 x, inout LightSample ls) {
    vec3 toLight = light.position - x;
    float d2 = dot(toLight, toLight);
    if (!(d2 > 0.0)) return false;
    ls.dist = sqrt(d2);
    ls.wi = toLight / ls.dist;
    float falloff = spotFalloff(light, -ls.wi);
    if (!(falloff > 0.0)) return false;
    ls.radiance = light.emission * (falloff / d2);  // I s^2 / d^2
    ls.pdf = 1.0;
    ls.isDelta = true;
    return true;
}

#endif
