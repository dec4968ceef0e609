// Shelf layout of the texture atlas (see texture_atlas_layout.h).
#include "scene/texture_atlas_layout.h"

#include <algorithm>
#include <numeric>

namespace penumbra {

std::optional<AtlasLayout> layoutTextureAtlas(const std::vector<glm::uvec2>& sizes, size_t* firstMisfit) {
    AtlasLayout layout;
    layout.origins.resize(sizes.size(), glm::uvec2(0));
    if (sizes.empty()) return layout;
    auto padded = [&](size_t i) { return sizes[i] + glm::uvec2(2 * kAtlasGutter); };
    for (size_t i = 0; i < sizes.size(); ++i)
        if (padded(i).x > kAtlasMaxSize || padded(i).y > kAtlasMaxSize) {
            if (firstMisfit) *firstMisfit = i;
            return std::nullopt;
        }

    // One row when they fit one, so that a few textures make a small image.
    uint64_t rowWidth = 0;
    for (size_t i = 0; i < sizes.size(); ++i) rowWidth += padded(i).x;
    layout.width = uint32_t(std::min<uint64_t>(rowWidth, kAtlasMaxSize));

    // Tallest first (ties in input order, so the layout depends on the scene alone).
    std::vector<size_t> order(sizes.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return padded(a).y > padded(b).y; });
    uint32_t shelfY = 0, shelfHeight = 0, x = 0;
    for (size_t i : order) {
        glm::uvec2 p = padded(i);
        if (x + p.x > layout.width) {  // next shelf
            shelfY += shelfHeight;
            shelfHeight = 0;
            x = 0;
        }
        if (shelfHeight == 0) shelfHeight = p.y;
        if (uint64_t(shelfY) + shelfHeight > kAtlasMaxSize) {
            if (firstMisfit) *firstMisfit = i;
            return std::nullopt;
        }
        layout.origins[i] = glm::uvec2(x, shelfY) + glm::uvec2(kAtlasGutter);
        x += p.x;
    }
    layout.height = shelfY + shelfHeight;
    return layout;
}

}  // namespace penumbra
