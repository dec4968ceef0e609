// Which layer the preview shows (the A key, docs/guide/preview.md): the tone-mapped image
// ("rgb") or one of the scene's film.aovs, as image/aov_false_color.h pictures it. The
// state and the layer -> pixels mapping, kept apart from the window so they test alone.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "image/image.h"

namespace penumbra::preview {

class LayerCycle {
public:
    explicit LayerCycle(std::vector<std::string> aovs) : m_aovs(std::move(aovs)) {}

    // rgb -> film.aovs[0] -> ... -> the last -> rgb. Without AOVs it stays on rgb and
    // returns false (nothing to cycle through), else true.
    bool next() {
        if (m_aovs.empty()) return false;
        m_index = (m_index + 1) % (m_aovs.size() + 1);
        return true;
    }
    bool showsRgb() const { return m_index == 0; }
    // "rgb" or the AOV's name.
    std::string name() const { return showsRgb() ? "rgb" : m_aovs[m_index - 1]; }

private:
    std::vector<std::string> m_aovs;
    size_t m_index = 0;  // 0: rgb, k: m_aovs[k - 1]
};

// The AOV layer `name` of `image` (a Renderer readback) as the tone map's pixels: RGBA8
// packed R | G << 8 | B << 16 | 255 << 24 per pixel (shaders/preview/tonemap.comp), each
// the sRGB encoding of aovFalseColor (exposure and the tone curve are for radiance: not
// applied). Throws std::logic_error when the image has no such layer.
std::vector<uint32_t> layerPixels(const Image& image, const std::string& name);

}  // namespace penumbra::preview
