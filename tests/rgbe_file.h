// Writes Radiance HDR (RGBE) files for the tests, so that an environment map can be given in
// both formats the contract names: flat (not run-length encoded) scanlines, which every
// reader accepts (Greg Ward, "Real Pixels", Graphics Gems II; stb_image's reader).
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra::test {

// One pixel: the shared exponent of the largest component, mantissas in 1/256 of 2^e.
// Values of the form k 2^(e - 8) with k < 256 survive exactly (stb decodes m 2^(e - 136)).
inline void encodeRgbe(glm::vec3 c, uint8_t out[4]) {
    float largest = std::max({c.x, c.y, c.z});
    if (!(largest > 1e-32f)) {
        out[0] = out[1] = out[2] = out[3] = 0;
        return;
    }
    int e = 0;
    float m = std::frexp(largest, &e) * 256.0f / largest;  // largest = frac 2^e, frac in [0.5, 1)
    out[0] = uint8_t(c.x * m);
    out[1] = uint8_t(c.y * m);
    out[2] = uint8_t(c.z * m);
    out[3] = uint8_t(e + 128);
}

// `texels`: width * height, row 0 at the top.
inline void writeRgbeHdr(const std::filesystem::path& path, uint32_t width, uint32_t height,
                         const std::vector<glm::vec3>& texels) {
    std::ofstream out(path, std::ios::binary);
    out << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " << height << " +X " << width << "\n";
    for (const glm::vec3& t : texels) {
        uint8_t rgbe[4];
        encodeRgbe(t, rgbe);
        out.write(reinterpret_cast<const char*>(rgbe), 4);
    }
}

}  // namespace penumbra::test
