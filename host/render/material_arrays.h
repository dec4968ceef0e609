// Scene materials -> the GPU Material records the kernels read (shaders/shared/types.h,
// MATERIAL_TEXELS texels each): one packing per material kind, in material_arrays.cpp.
#pragma once

#include <vector>

#include "scene/scene.h"
#include "shared/types.h"

namespace penumbra {

gpu::Material packMaterial(const Material& m);

// One record per scene material, in order; a scene without materials still gets the
// default diffuse 0.8, so that index 0 always exists.
std::vector<gpu::Material> packMaterials(const std::vector<Material>& materials);

}  // namespace penumbra
