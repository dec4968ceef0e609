// 8-bit sRGB PNG output for a quick look at a render: radiance times 2^exposure, through
// the tone curve (tone_map.h: clamp or filmic) into [0, 1], encoded with the exact sRGB
// transfer function (IEC 61966-2-1).
// EXR stays the real output; this one is lossy by design.
#include <cmath>
#include <stdexcept>
#include <string>

#include "image/atomic_file.h"
#include "image/image.h"
#include "image/stb_image_write_static.h"

namespace penumbra {

uint8_t linearToSrgb8(float linear) {
    // !(x > 0) also catches NaN, which maps to black rather than to undefined bytes.
    if (!(linear > 0.0f)) return 0;
    if (linear >= 1.0f) return 255;
    const double x = linear;
    const double encoded = x < 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return uint8_t(std::floor(encoded * 255.0 + 0.5));  // round to nearest code value
}

void writePng(const std::filesystem::path& path, const Image& image, ToneLook look) {
    if (image.rgb.size() != size_t(image.width) * image.height * 3)
        throw std::runtime_error("failed to write " + path.string() + ": pixel buffer does not match the image size");
    const float scale = std::exp2(look.exposure);
    std::vector<uint8_t> bytes(image.rgb.size());
    for (size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = linearToSrgb8(applyToneCurve(image.rgb[i] * scale, look.curve));
    writePngRgb8(path, image.width, image.height, bytes);
}

void writePngRgb8(const std::filesystem::path& path, uint32_t width, uint32_t height, const std::vector<uint8_t>& rgb) {
    if (width == 0 || height == 0 || width > INT32_MAX / 3 || height > INT32_MAX)
        throw std::runtime_error("failed to write " + path.string() + ": invalid image size " + std::to_string(width) +
                                 "x" + std::to_string(height));
    if (rgb.size() != size_t(width) * height * 3)
        throw std::runtime_error("failed to write " + path.string() + ": pixel buffer does not match the image size");

    // Encode to memory first: stb's own file writer does not report write errors.
    std::string encoded;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
    };
    if (!stbi_write_png_to_func(append, &encoded, int(width), int(height), 3, rgb.data(), int(width) * 3))
        throw std::runtime_error("failed to write " + path.string() + ": PNG encoding failed");

    writeOutputFile(path, encoded);
}

}  // namespace penumbra
