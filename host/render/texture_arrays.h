// The GPU arrays of material textures and texture coordinates (shaders/shared/types.h,
// "Textures"): per-material texture references, the atlas image of every texture's
// half-float texels with their gutters, and per-primitive mesh uvs. Empty (the atlas
// 1 x 1) for an untextured scene.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/bvh.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace penumbra {

struct TextureArrays {
    bool textured = false;                     // some material has a textured field
    std::vector<glm::uvec4> materialTextures;  // BINDING_MATERIAL_TEXTURES
    uint32_t atlasWidth = 1, atlasHeight = 1;  // BINDING_TEXTURE_ATLAS
    std::vector<uint16_t> atlas = std::vector<uint16_t>(4, 0);  // RGBA halves, row 0 first
    std::vector<gpu::TriangleUvs> uvs;         // BINDING_UVS, in the BVH's leaf order
};

// `bvh` is the scene's, built from its shapes' primitives in order (one per sphere and
// quad, one per mesh triangle), so that leaf i's uvs are those of input primitive
// bvh.originalIndex[i]. Throws InputError when the textures do not fit the atlas
// (buildTextureAtlas).
TextureArrays buildTextureArrays(const Scene& scene, const Bvh& bvh);

// The GPU slot of a scene-side TextureSlot (TEXTURE_SLOT_*).
uint32_t gpuTextureSlot(TextureSlot slot);

}  // namespace penumbra
