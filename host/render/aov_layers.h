// The AOV layers of a render (SCENE_FORMAT.md "AOVs (v3)"): which the kernel accumulates
// (SPEC_AOVS bits) and how the per-pixel sums of the AOV buffer (shared/aov.h) become the
// image's layers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/bvh.h"
#include "image/image.h"
#include "scene/scene.h"

namespace penumbra {

// AOV_* bits of the names (scene/aov_names.h checked them); 0 for none.
uint32_t aovBits(const std::vector<std::string>& names);

// The layers `names`, in that order, from the AOV sums (AOV_VEC4S vec4 per pixel) and the
// radiance means of `image` (for the variance). The ids map the centre ray's primitive
// (leaf order) through `bvh` to its shape in scene.shapes, its triangle within the shape,
// and its material (SCENE_FORMAT.md's numbering).
std::vector<AovLayer> aovLayers(const std::vector<std::string>& names, const std::vector<glm::vec4>& sums,
                                const Image& image, const Scene& scene, const Bvh& bvh);

}  // namespace penumbra
