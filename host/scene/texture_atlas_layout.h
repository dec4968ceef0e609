// Where every texture sits in the one RGBA16F atlas image the kernels sample
// (shaders/textures/textures.glsl): shelves of textures sorted by height, each inside a
// 1-texel gutter, in an image of at most kAtlasMaxSize texels on a side. The loaders
// check a scene's textures against it; the renderer fills the atlas from it.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra {

// lavapipe's maxImageDimension2D (the Vulkan minimum is 4096; render/texture_arrays.cpp
// checks the device's).
inline constexpr uint32_t kAtlasMaxSize = 16384;
// Texels of gutter on every side of a texture: its repeat neighbours, so that the
// sampler's 2 x 2 footprint at an edge reads what wrapping would (texture_arrays.cpp).
inline constexpr uint32_t kAtlasGutter = 1;
// The largest texture side that fits an atlas with its gutters.
inline constexpr uint32_t kAtlasMaxTextureSide = kAtlasMaxSize - 2 * kAtlasGutter;

struct AtlasLayout {
    uint32_t width = 0, height = 0;   // of the atlas image, in texels (0 x 0: no textures)
    std::vector<glm::uvec2> origins;  // per texture: the atlas texel of its texel (0, 0)
};

// Lays out textures of `sizes` (width, height) on shelves: the textures by decreasing
// height (next-fit decreasing height, Coffman et al. 1980), each shelf as tall as its
// first, the atlas as wide as one row of all textures or kAtlasMaxSize. nullopt when
// they do not fit kAtlasMaxSize x kAtlasMaxSize; `firstMisfit` is then the texture at
// which the layout ran out of room.
std::optional<AtlasLayout> layoutTextureAtlas(const std::vector<glm::uvec2>& sizes, size_t* firstMisfit = nullptr);

}  // namespace penumbra
