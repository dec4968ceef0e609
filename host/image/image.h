// Images on the host: linear RGB float pixels with Penumbra's render metadata, and the
// operations the command line offers on them (EXR/PNG files, merge, compare).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "image/tone_map.h"

namespace penumbra {

// A run of sample indices of one seed, [first, end): a render of spp samples with
// sample_offset K covers (seed, K, K + spp); a merge covers the union of its inputs'.
struct SamplePiece {
    int64_t seed = 0;
    int64_t first = 0;
    int64_t end = 0;
    bool operator==(const SamplePiece&) const = default;
};

// The EXR header attributes of SCENE_FORMAT.md; absent ones are nullopt.
struct ImageMetadata {
    std::optional<int> spp;               // penumbra:spp
    std::optional<int> seed;              // penumbra:seed
    std::optional<int> sampleOffset;      // penumbra:sample_offset
    std::optional<std::string> integrator;  // penumbra:integrator (JSON text)
    std::optional<double> renderSeconds;  // penumbra:render_seconds
    // penumbra:sampler, "sobol" or "independent": beyond SCENE_FORMAT.md's list (docs/design/contract-decisions.md).
    // Renders made before the sampler option lack it; they used independent samples.
    std::optional<std::string> sampler;
    // penumbra:pieces (docs/design/contract-decisions.md): the exact sample pieces of a merged image, written by merge
    // as "SEED:FIRST-END,..." (END exclusive). Absent in renders: one piece, from the above.
    std::optional<std::vector<SamplePiece>> pieces;
};

// "0:0-8,0:16-24" and back; parsing throws std::invalid_argument("why") on malformed
// text, negative or empty ranges, or pieces that overlap.
std::string formatSamplePieces(const std::vector<SamplePiece>& pieces);
std::vector<SamplePiece> parseSamplePieces(const std::string& text);
// The pieces an image covers: penumbra:pieces if present, else the one piece of (seed,
// sample_offset (absent: 0), spp); empty when the seed or spp is unknown.
std::vector<SamplePiece> samplePiecesOf(const ImageMetadata& meta);
// Sorted by (seed, first), touching runs of one seed joined.
std::vector<SamplePiece> normalizeSamplePieces(std::vector<SamplePiece> pieces);

// One AOV layer (SCENE_FORMAT.md "AOVs (v3)"): float channels (`floats`, channels.size()
// per pixel, interleaved) or one uint channel of ids (`ids`, one per pixel).
struct AovLayer {
    std::string name;                   // "albedo", ..., as in film.aovs
    std::vector<std::string> channels;  // EXR channel names, e.g. "albedo.R"
    std::vector<float> floats;
    std::vector<uint32_t> ids;
};

struct Image {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<float> rgb;  // width * height * 3, row-major, pixel (0,0) top left
    ImageMetadata meta;
    std::vector<AovLayer> aovs;  // film.aovs' layers, in that order; written beside R, G, B

    float* pixel(uint32_t x, uint32_t y) { return &rgb[(size_t(y) * width + x) * 3]; }
    const float* pixel(uint32_t x, uint32_t y) const { return &rgb[(size_t(y) * width + x) * 3]; }
};

// Writes R, G, B as 32-bit float, the AOV layers and the metadata as header attributes.
// Atomic: writes a temporary file beside `path` and renames it; throws
// std::runtime_error on failure.
void writeExr(const std::filesystem::path& path, const Image& image);
// Reads an EXR (R, G, B, and the AOV layers that penumbra:aovs names; missing channels
// are an error). Throws InputError("FILE: why").
Image readExr(const std::filesystem::path& path);
// Its size, penumbra:* metadata and AOV layer names alone (rgb and the layers' pixels
// empty), with the same checks of the header: what merge and compare check before they
// read any pixel.
Image readExrHeader(const std::filesystem::path& path);
// The same for the bytes of an EXR file held in memory, with the same checks and errors;
// `name` stands for the file in messages ("NAME: why").
Image decodeExr(std::string_view bytes, const std::string& name);
// The same, the pixels decoded straight into `rgba` (4 floats a pixel, alpha 1; the result's
// rgb stays empty) once `acceptSize(width, height)` has returned (it throws to refuse): an
// RGBA reader (image_file.cpp) then holds no RGB copy of a large image.
Image decodeExrRgba(std::string_view bytes, const std::string& name, std::vector<float>& rgba,
                    const std::function<void(uint32_t, uint32_t)>& acceptSize);
// sRGB 8-bit PNG of radiance times 2^look.exposure through look.curve (tone_map.h);
// atomic like writeExr.
void writePng(const std::filesystem::path& path, const Image& image, ToneLook look = {});
// 8-bit sRGB encoding of one linear value (clamped), shared with the preview's tone map.
uint8_t linearToSrgb8(float linear);
// A PNG of already encoded 8-bit sRGB bytes (width * height * 3, row-major, top row first),
// e.g. the preview's tone-mapped screen; atomic like writeExr.
void writePngRgb8(const std::filesystem::path& path, uint32_t width, uint32_t height, const std::vector<uint8_t>& rgb);

// Averages partial renders weighted by penumbra:spp; the result's spp is their sum.
// Throws InputError naming the file when sizes differ, spp is missing, or two partials
// with the same seed overlap in sample indices. `names` label the images in messages.
// Pixels that are NaN, infinite or negative are refused too (no render holds them).
// AOV layers are merged too (image/merge_aovs.h): the inputs must have the same list.
Image mergeImages(const std::vector<Image>& images, const std::vector<std::string>& names);
// The checks of mergeImages that need only the headers (readExrHeader): run on every input
// before any pixels are read, so that a bad input costs no image's memory.
void checkMergeHeaders(const std::vector<Image>& images, const std::vector<std::string>& names);

struct CompareMetrics {
    double rmse = 0;    // sqrt(mean (a-b)^2)
    double relmse = 0;  // mean (a-b)^2 / (b^2 + 1e-2)
    double meanA = 0;
    double meanB = 0;
    double maxAbs = 0;  // max |a-b|
};
// Over all pixels and channels; throws InputError when the sizes differ.
CompareMetrics compareImages(const Image& a, const Image& b);
// The same, with the file names that a size mismatch error names (InputError "A: ...").
CompareMetrics compareImages(const Image& a, const Image& b, const std::string& nameA, const std::string& nameB);

}  // namespace penumbra
