// Filling the texture atlas (see texture_atlas.h).
#include "render/texture_atlas.h"

#include <cstring>
#include <optional>
#include <string>

#include "core/errors.h"
#include "scene/texture_atlas_layout.h"

namespace penumbra {

TextureAtlas buildTextureAtlas(const std::vector<Texture>& textures) {
    std::vector<glm::uvec2> sizes;
    for (const Texture& t : textures) sizes.emplace_back(t.width, t.height);
    std::optional<AtlasLayout> layout = layoutTextureAtlas(sizes);
    if (!layout)
        throw InputError("the scene's textures do not fit one " + std::to_string(kAtlasMaxSize) + " x " +
                         std::to_string(kAtlasMaxSize) + " texture atlas (README: texture limits)");
    TextureAtlas atlas;
    if (layout->width > 0 && layout->height > 0) {
        atlas.width = layout->width;
        atlas.height = layout->height;
        atlas.texels.assign(size_t(atlas.width) * atlas.height * 4, 0);
    }
    // Every texture inside a gutter of the texels that repeat wrapping puts next to its
    // edges (the opposite edge; at the corners the opposite corner). The sampler's 2 x 2
    // footprint within half a texel of an edge then blends what the contract's repeat
    // filtering blends; clamp and mirror lookups never weigh the gutter (textures.glsl).
    static_assert(kAtlasGutter == 1, "the copies below write one gutter texel per side");
    for (size_t i = 0; i < textures.size(); ++i) {
        const Texture& t = textures[i];
        const glm::uvec2 origin = layout->origins[i];
        atlas.origins.push_back(origin.x | origin.y << 16);
        if (t.width == 0 || t.height == 0) continue;
        const int64_t w = t.width, h = t.height;
        for (int64_t y = -1; y <= h; ++y) {
            const int64_t sy = (y + h) % h;  // the gutter rows -1 and h: rows h - 1 and 0
            uint16_t* row = &atlas.texels[size_t(((int64_t(origin.y) + y) * atlas.width + origin.x - 1) * 4)];
            const uint16_t* src = &t.texels[size_t(sy * w * 4)];
            std::memcpy(row, src + (w - 1) * 4, 8);    // left gutter: the last column
            std::memcpy(row + 4, src, size_t(w) * 8);  // the row itself
            std::memcpy(row + (w + 1) * 4, src, 8);    // right gutter: the first column
        }
    }
    return atlas;
}

}  // namespace penumbra
