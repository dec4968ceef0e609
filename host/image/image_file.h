// Reading image files as data (textures, environment maps): PNG, JPEG and Radiance HDR
// through stb_image, OpenEXR through exr.cpp's hardened reader, into linear float RGBA.
// The format is told by the file's first bytes, not its name. Scene validation (which
// field names the file) is the caller's: errors here name the file only.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {

// Largest image accepted: each side at most kMaxImageSide and at most kMaxImagePixels
// pixels in all (8192 x 8192, 1 GiB as float RGBA), checked from the header before any
// pixel is decoded, so that a corrupt or hostile header cannot ask for gigabytes.
inline constexpr uint32_t kMaxImageSide = 16384;
inline constexpr uint64_t kMaxImagePixels = uint64_t(1) << 26;
// Image files larger than this are refused before they are read (1 GiB).
inline constexpr uint64_t kMaxImageFileBytes = uint64_t(1) << 30;

// How 8- and 16-bit integer data (PNG, JPEG) becomes linear: Srgb applies the sRGB
// decoding curve (IEC 61966-2-1) to R, G and B (never to alpha), for colour data; Linear
// only divides by the largest code value, for data such as glTF's metallic-roughness
// maps. Float data (HDR, EXR) is linear already and never changed.
enum class ColorDecode { Linear, Srgb };

enum class ImageFileFormat { Png, Jpeg, Hdr, Exr };

struct ImageFile {
    uint32_t width = 0;
    uint32_t height = 0;
    ImageFileFormat format = ImageFileFormat::Png;
    uint32_t channels = 0;    // in the file: 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA
    std::vector<float> rgba;  // width * height * 4, row-major, row 0 = the image's top row;
                              // grey is copied to R, G and B; alpha 1 where the file has none

    const float* texel(uint32_t x, uint32_t y) const { return &rgba[(size_t(y) * width + x) * 4]; }
};

// Called with an image's size as its header gives it, after the limits above and before
// any pixel is decoded, so that a caller with limits of its own (the texels of all of a
// scene's textures) refuses the image by throwing before it costs memory or time.
using AcceptImageSize = std::function<void(uint32_t width, uint32_t height)>;

// Throws InputError("<label>: <why>") for a missing or unreadable file, an unsupported
// format, corrupt data, or dimensions beyond the limits above; `maxPixels` (at most
// kMaxImagePixels) lowers the pixel limit for a caller with a smaller one (checked from the
// header, before any pixel is decoded).
ImageFile readImageFile(const std::filesystem::path& path, const std::string& label, ColorDecode decode,
                        uint64_t maxPixels = kMaxImagePixels, const AcceptImageSize& accept = {});
inline ImageFile readImageFile(const std::filesystem::path& path, ColorDecode decode) {
    return readImageFile(path, path.string(), decode);
}

// The same for an image held in memory (e.g. embedded in a glTF model): PNG, JPEG and HDR.
ImageFile decodeImage(const std::string& bytes, const std::string& label, ColorDecode decode,
                      uint64_t maxPixels = kMaxImagePixels, const AcceptImageSize& accept = {});

// The width and height of a PNG, JPEG or HDR image in memory, from its header alone (no
// pixel decoded), after the limits above; InputError as decodeImage for anything else.
std::pair<uint32_t, uint32_t> imageSize(const std::string& bytes, const std::string& label);

// The sRGB decoding curve for one value in [0, 1] (IEC 61966-2-1), the inverse of
// linearToSrgb8's encoding.
float srgbToLinear(float encoded);

}  // namespace penumbra
