// Directional light (SCENE_FORMAT.md `directional`): irradiance E arriving from one direction
// at infinity. A delta light: its one direction is sampled with "pdf" 1, it cannot be hit.
#ifndef PENUMBRA_LIGHTS_DIRECTIONAL_GLSL
#define PENUMBRA_LIGHTS_DIRECTIONAL_GLSL

#include "lights/light_sample.glsl"

bool sampleDirectionalLight(Light light, inout LightSample ls) {
    ls.wi = -light.position;  // position holds the unit direction of travel
    ls.radiance = light.emission;
    ls.pdf = 1.0;
    ls.isDelta = true;
    return true;
}

#endif
