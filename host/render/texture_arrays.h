// The GPU arrays of material textures and texture coordinates (shaders/shared/types.h,
// "Textures"): per-material texture references, every texture's half-float texels packed
// two per RGBA32UI texel, and per-primitive mesh uvs. Empty for an untextured scene.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "bvh/bvh.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace penumbra {

struct TextureArrays {
    bool textured = false;                        // some material has a textured field
    bool transformed = false;                     // and some of them a uv transform (TEXTURES_TRANSFORMED)
    bool emission = false;                        // an emitter's material has an emission texture (TEXTURES_EMISSION)
    bool alphaMask = false;                       // some material has an alpha test (TEXTURES_ALPHA_MASK)
    bool normalMap = false;                       // some material has a normal map (TEXTURES_NORMAL_MAP)
    std::vector<glm::uvec4> materialTextures;     // BINDING_MATERIAL_TEXTURES
    std::vector<glm::uvec4> texels;               // BINDING_TEXTURE_TEXELS
    std::vector<gpu::TriangleUvs> uvs;            // BINDING_UVS, in the BVH's leaf order
    std::vector<gpu::TriangleTangents> tangents;  // BINDING_TANGENTS, leaf order; empty without normal maps
};

// `bvh` is the scene's, built from its shapes' primitives in order (one per sphere and
// quad, one per mesh triangle), so that leaf i's uvs are those of input primitive
// bvh.originalIndex[i].
TextureArrays buildTextureArrays(const Scene& scene, const Bvh& bvh);

// The GPU slot of a scene-side TextureSlot (TEXTURE_SLOT_*).
uint32_t gpuTextureSlot(TextureSlot slot);

}  // namespace penumbra
