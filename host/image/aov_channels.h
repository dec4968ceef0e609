// The EXR channels of each AOV layer (SCENE_FORMAT.md "AOVs (v3)"), in one place for the
// three that need them: the renderer names its layers' channels (render/aov_layers.cpp),
// the EXR reader reads them back (image/exr.cpp) and merge combines them (image/merge.cpp).
// Which names a scene may ask for is checked by scene/aov_names.h ("denoised" is not one).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

// The ids are one uint channel each, named as the layer.
inline bool aovHoldsIds(std::string_view name) {
    return name == "shape_id" || name == "primitive_id" || name == "material_id";
}

// The layer's channels in EXR order; empty for a name that is no AOV.
inline std::vector<std::string> aovChannels(std::string_view name) {
    const std::string n(name);
    // "denoised" is no film.aovs name: `render --denoise` adds it (python/penumbra/denoise_exr.py).
    if (name == "albedo" || name == "variance" || name == "denoised") return {n + ".R", n + ".G", n + ".B"};
    if (name == "normal" || name == "position") return {n + ".X", n + ".Y", n + ".Z"};
    if (name == "depth") return {"depth.Z"};
    if (aovHoldsIds(name)) return {n};
    return {};
}

}  // namespace penumbra
