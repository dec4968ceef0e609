// The texture atlas image (BINDING_TEXTURE_ATLAS, shaders/shared/types.h "Textures"):
// every texture's RGBA half texels at its place in the layout of
// scene/texture_atlas_layout.h, inside a 1-texel gutter of its repeat neighbours.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace penumbra {

struct TextureAtlas {
    uint32_t width = 1, height = 1;                              // 1 x 1 (zero) without textures
    std::vector<uint16_t> texels = std::vector<uint16_t>(4, 0);  // RGBA halves, row 0 first
    std::vector<uint32_t> origins;  // per texture: its texel (0, 0) in the atlas, x | y << 16
};

// Throws InputError when the textures do not fit the atlas (the loaders refuse such
// scenes first: TextureTable::checkAtlas).
TextureAtlas buildTextureAtlas(const std::vector<Texture>& textures);

}  // namespace penumbra
