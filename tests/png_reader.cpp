// The one stb_image implementation of the test binary (see png_reader.h).
#include "png_reader.h"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_image.h>
#pragma GCC diagnostic pop

namespace penumbra::test {

Png readPng(const std::filesystem::path& path, int channels) {
    Png png;
    uint8_t* data = stbi_load(path.c_str(), &png.width, &png.height, &png.channelsInFile, channels);
    if (!data) return Png{};
    int n = channels ? channels : png.channelsInFile;
    png.pixels.assign(data, data + size_t(png.width) * png.height * n);
    stbi_image_free(data);
    return png;
}

}  // namespace penumbra::test
