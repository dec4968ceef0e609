// An AOV layer -> the preview's pixels (see layer_cycle.h).
#include "preview/layer_cycle.h"

#include <stdexcept>

#include "image/aov_false_color.h"

namespace penumbra::preview {

std::vector<uint32_t> layerPixels(const Image& image, const std::string& name) {
    const size_t pixels = size_t(image.width) * image.height;
    for (const AovLayer& layer : image.aovs) {
        if (layer.name != name) continue;
        const std::vector<float> rgb = aovFalseColor(layer, pixels);
        std::vector<uint32_t> packed(pixels);
        for (size_t i = 0; i < pixels; ++i)
            packed[i] = uint32_t(linearToSrgb8(rgb[3 * i])) | uint32_t(linearToSrgb8(rgb[3 * i + 1])) << 8 |
                        uint32_t(linearToSrgb8(rgb[3 * i + 2])) << 16 | 0xff000000u;
        return packed;
    }
    throw std::logic_error("layerPixels: the image has no layer " + name);
}

}  // namespace penumbra::preview
