// Point light (lecture, "Point Light"; SCENE_FORMAT.md `point`): isotropic intensity I (W/sr)
// at a position. A delta light: its one direction is sampled with "pdf" 1, it cannot be hit,
// and its density for any other strategy's direction is 0.
#ifndef PENUMBRA_LIGHTS_POINT_GLSL
#define PENUMBRA_LIGHTS_POINT_GLSL

#include "lights/light_sample.glsl"

// The direction toward the light from x, and the irradiance-like term I / d^2 it delivers.
bool samplePointLight(Light light, vec3 x, inout LightSample ls) {
    vec3 toLight = light.position - x;
    float d2 = dot(toLight, toLight);
    if (!(d2 > 0.0)) return false;
    ls.dist = sqrt(d2);
    ls.wi = toLight / ls.dist;
    ls.radiance = light.emission / d2;  // I / d^2 (lecture, "Point Light")
    ls.pdf = 1.0;
    ls.isDelta = true;
    return true;
}

#endif
