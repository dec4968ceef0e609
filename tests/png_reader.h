// Reading PNGs back in tests (stb_image, compiled once for the test binary).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace penumbra::test {

struct Png {
    int width = 0, height = 0;
    int channelsInFile = 0;
    std::vector<uint8_t> pixels;  // width * height * channels (as asked, or as in the file)
};

// An empty Png (width 0) when the file cannot be read. `channels` 0 keeps the file's.
Png readPng(const std::filesystem::path& path, int channels = 3);

}  // namespace penumbra::test
