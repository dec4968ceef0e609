// Studio lighting for a model without lights (see model_lighting.h).
#include "scene/model_lighting.h"

#include <sstream>

#include <glm/geometric.hpp>

namespace penumbra {

std::vector<Light> modelStudioLights(const Camera& camera) {
    // The key comes from the front, 45 degrees to the camera's left and 45 degrees above its
    // view axis (the photographer's classic key position), so that the faces the camera sees
    // are lit and the shadow falls behind and to the right of the model.
    glm::vec3 view = glm::normalize(camera.target - camera.eye);
    glm::vec3 right = glm::normalize(glm::cross(view, camera.up));
    glm::vec3 up = glm::cross(right, view);
    glm::vec3 towardKey = glm::normalize(-view - right + glm::sqrt(2.0f) * up);

    Light sky;
    sky.type = LightType::Environment;
    sky.intensity = glm::vec3(kModelSkyRadiance);
    Light key;
    key.type = LightType::Directional;
    key.direction = -towardKey;  // the way the light travels
    key.intensity = glm::vec3(kModelKeyIrradiance);
    return {sky, key};
}

std::string modelStudioLightsNote() {
    std::ostringstream note;
    note << "no lights in the model; lit by a sky (radiance " << kModelSkyRadiance << ") and a key light (irradiance "
         << kModelKeyIrradiance << ") from the camera's upper left (--set lights=[] for none)";
    return note.str();
}

}  // namespace penumbra
