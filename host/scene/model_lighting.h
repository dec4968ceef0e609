// The lights a glTF model rendered on its own gets when it brings none (SCENE_FORMAT.md
// "glTF input"; the choice of sky and key light is recorded in
// docs/design/contract-decisions.md).
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace penumbra {

// A constant sky plus a directional key light from above and to the left of the camera,
// as a model viewer's default studio lighting: the sky alone lights a model flatly (every
// face of a white box the same grey), the key light gives its faces their shading.
inline constexpr float kModelSkyRadiance = 0.4f;
inline constexpr float kModelKeyIrradiance = 2.0f;

std::vector<Light> modelStudioLights(const Camera& camera);

// The note that says so: "no lights in the model; lit by a sky (radiance 0.4) and ...".
std::string modelStudioLightsNote();

}  // namespace penumbra
