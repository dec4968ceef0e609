// Image files as linear float RGBA (see image_file.h): the bytes read by readInputFile,
// the format from the magic bytes, the size from the header (refused past the limits
// before decoding), then stb_image for PNG, JPEG and HDR, exr.cpp's decodeExr for OpenEXR.
#include "image/image_file.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>

#include "core/errors.h"
#include "core/input_file.h"
#include "core/stop_request.h"
#include "image/image.h"

// Static, so that another copy in the same program (the tests have one, tinygltf may
// bring one) never clashes with ours; only the formats Penumbra reads are compiled in.
// stb_image refuses a side above STBI_MAX_DIMENSIONS itself as well.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_ONLY_HDR
#define STBI_NO_STDIO
#define STBI_MAX_DIMENSIONS 16384
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb_image.h>
#pragma GCC diagnostic pop

namespace penumbra {
namespace {

static_assert(STBI_MAX_DIMENSIONS == kMaxImageSide);

// OpenEXR's magic number, the first 4 bytes of every EXR file.
constexpr const char* kExrMagic = "\x76\x2f\x31\x01";

bool startsWith(const std::string& bytes, const char* magic, size_t n) {
    return bytes.size() >= n && std::memcmp(bytes.data(), magic, n) == 0;
}

void checkSize(int64_t width, int64_t height, const std::string& label, uint64_t maxPixels) {
    if (width <= 0 || height <= 0) throwInputError(label, "", "image has no pixels");
    maxPixels = std::min(maxPixels, kMaxImagePixels);
    if (width > kMaxImageSide || height > kMaxImageSide || uint64_t(width) * uint64_t(height) > maxPixels)
        throwInputError(label, "",
                        "image is " + std::to_string(width) + "x" + std::to_string(height) +
                            ", larger than the limit (each side <= 16384, at most " + std::to_string(maxPixels) +
                            " pixels)");
}

// stb's failure reason is a short phrase ("bad huffman code", "corrupt PNG").
[[noreturn]] void stbFailed(const std::string& label, const char* what) {
    const char* reason = stbi_failure_reason();
    throwInputError(label, "", std::string("cannot decode ") + what + " image: " + (reason ? reason : "corrupt data"));
}

struct StbFree {
    void operator()(void* p) const { stbi_image_free(p); }
};

// Where stb_image's HDR loader starts reading pixels: after the header lines up to the
// first empty one and the resolution line, each read by stb's own line reader, which also
// ends a line at 1023 bytes and counts a line that starts with a NUL byte as empty. Found
// with that reader rather than by searching for "\n\n", so that checkHdrData walks the
// very bytes stb decodes (a NUL line once made the two disagree, and stb hung).
size_t hdrPixelDataStart(const std::string& bytes) {
    stbi__context context;
    stbi__start_mem(&context, reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()));
    char line[STBI__HDR_BUFLEN];
    stbi__hdr_gettoken(&context, line);  // "#?RADIANCE" or "#?RGBE", checked by stbi__hdr_info
    while (stbi__hdr_gettoken(&context, line)[0] != 0) {
    }
    stbi__hdr_gettoken(&context, line);  // "-Y h +X w"
    return size_t(context.img_buffer - context.img_buffer_original);
}

// Walks Radiance HDR pixel data as stb_image will read it, and refuses data that ends early
// or holds a run of length 0: stb reads past the end as zeros and, in a run-length encoded
// scanline, loops forever on a count of 0 (a truncated file hung the program). `bytes` is the
// whole file, `w` x `h` its size from the header (Greg Ward's format: header lines, an empty
// line, the resolution line, then scanlines, each flat RGBE or "2 2 w_hi w_lo" and runs).
void checkHdrData(const std::string& bytes, int64_t w, int64_t h, const std::string& label) {
    auto corrupt = [&](const char* why) { throwInputError(label, "", std::string("cannot decode HDR image: ") + why); };
    size_t at = hdrPixelDataStart(bytes);
    auto left = [&] { return bytes.size() - at; };
    auto byte = [&](size_t i) { return uint8_t(bytes[at + i]); };
    const uint64_t pixels = uint64_t(w) * uint64_t(h);
    // stb reads flat pixels when the width cannot be run-length encoded.
    if (w < 8 || w >= 32768) {
        if (left() < 4 * pixels) corrupt("pixel data ends early");
        return;
    }
    for (int64_t row = 0; row < h; ++row) {
        if (left() < 4) corrupt("pixel data ends early");
        if (byte(0) != 2 || byte(1) != 2 || (byte(2) & 0x80)) {
            // Not run-length encoded: stb reads the rest of the image as flat pixels, from
            // these 4 bytes on, restarting at the first row.
            if (left() < 4 * pixels) corrupt("pixel data ends early");
            return;
        }
        if ((int64_t(byte(2)) << 8 | byte(3)) != w) corrupt("scanline length differs from the width");
        at += 4;
        for (int component = 0; component < 4; ++component)
            for (int64_t x = 0; x < w;) {
                if (left() < 1) corrupt("pixel data ends early");
                int count = byte(0);
                bool run = count > 128;
                if (run) count -= 128;
                if (count == 0 || count > w - x) corrupt("bad run length");
                size_t need = 1 + (run ? 1 : size_t(count));
                if (left() < need) corrupt("pixel data ends early");
                at += need;
                x += count;
            }
    }
}

// Walks a JPEG's marker segments and entropy-coded data (ITU-T T.81, B.1 and B.2) before
// stb_image reads any of it, and refuses what stb mishandles:
// - a Huffman table (DHT) whose 16 code counts add up to more than 256 codes, which
//   stb_image 2.27 writes past its 257-entry table for (found by tools/dev/fuzz);
// - data that ends before the end-of-image marker FF D9 (B.2.1): stb fills what is missing
//   with zeros, so a file cut short decoded into a wrong texture.
// Entropy-coded data holds FF only as FF 00 or a restart marker FF D0-D7 (B.1.1.5), so the
// next other marker ends it; an EXIF thumbnail's markers lie inside its APP1 segment and are
// skipped with it.
void checkJpegSegments(const std::string& bytes, const std::string& label) {
    auto corrupt = [&](const std::string& why) { throwInputError(label, "", "cannot decode JPEG image: " + why); };
    auto byte = [&](size_t i) { return uint8_t(bytes[i]); };
    size_t at = 2;  // after SOI
    while (true) {
        if (at + 2 > bytes.size()) corrupt("data ends early (no end-of-image marker)");
        if (byte(at) != 0xFF) corrupt("marker expected at byte " + std::to_string(at));
        const uint8_t marker = byte(at + 1);
        if (marker == 0xFF) {  // fill byte (B.1.1.2)
            ++at;
            continue;
        }
        if (marker == 0xD9) return;                                  // EOI
        if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {  // no length
            at += 2;
            continue;
        }
        if (at + 4 > bytes.size()) corrupt("data ends early (no end-of-image marker)");
        const size_t end = at + 2 + (size_t(byte(at + 2)) << 8 | byte(at + 3));
        if (end > bytes.size() || end < at + 4) corrupt("data ends early (no end-of-image marker)");
        if (marker == 0xC4) {  // DHT: tables of 1 + 16 count bytes and their symbols (B.2.4.2)
            for (size_t table = at + 4; table < end;) {
                if (table + 17 > end) corrupt("bad Huffman table");
                size_t codes = 0;
                for (size_t i = 1; i <= 16; ++i) codes += byte(table + i);
                if (codes > 256 || table + 17 + codes > end) corrupt("bad Huffman table");
                table += 17 + codes;
            }
        }
        at = end;
        if (marker == 0xDA)  // SOS: entropy-coded data up to the next marker
            while (at + 1 < bytes.size() &&
                   !(byte(at) == 0xFF && byte(at + 1) != 0x00 && !(byte(at + 1) >= 0xD0 && byte(at + 1) <= 0xD7)))
                at += byte(at) == 0xFF ? 2 : 1;
    }
}

// Refuses JPEG data too short for the size its header declares, before stb decodes it (a
// 1.6 KB file with a forged 8192 x 8192 header decoded for 18 s): every block of 8 x 8
// samples of a component at full resolution (one has it: T.81 A.1.1) codes its DC
// coefficient in at least one bit (a Huffman code is at least one bit long, T.81 C; stb
// reads no arithmetic coding), so the data has at least ceil(w / 8) * ceil(h / 8) bits.
void checkJpegSize(const std::string& bytes, int64_t w, int64_t h, const std::string& label) {
    const uint64_t minimumBits = uint64_t((w + 7) / 8) * uint64_t((h + 7) / 8);
    if (uint64_t(bytes.size()) * 8 < minimumBits)
        throwInputError(label, "",
                        "cannot decode JPEG image: data too short for its " + std::to_string(w) + "x" +
                            std::to_string(h) + " header (at least " + std::to_string((minimumBits + 7) / 8) +
                            " bytes, " + std::to_string(bytes.size()) + " found)");
}

const char* formatName(ImageFileFormat format) {
    return format == ImageFileFormat::Png ? "PNG" : format == ImageFileFormat::Jpeg ? "JPEG" : "HDR";
}

// Width, height and channels from the header alone, within the limits.
struct StbHeader {
    int width = 0, height = 0, channels = 0;
};

StbHeader readStbHeader(const std::string& bytes, const std::string& label, ImageFileFormat format,
                        uint64_t maxPixels) {
    if (bytes.size() > size_t(INT32_MAX)) throwInputError(label, "", "file too large");
    StbHeader header;
    // The format's own header reader: stbi_info_from_memory would go on to try every
    // other format and replace the reason ("too large") by "unknown image type".
    stbi__context context;
    stbi__start_mem(&context, reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()));
    int* w = &header.width;
    int* h = &header.height;
    int* n = &header.channels;
    if (format == ImageFileFormat::Jpeg) checkJpegSegments(bytes, label);  // before stb reads its tables
    int known = format == ImageFileFormat::Png    ? stbi__png_info(&context, w, h, n)
                : format == ImageFileFormat::Jpeg ? stbi__jpeg_info(&context, w, h, n)
                                                  : stbi__hdr_info(&context, w, h, n);
    if (!known) stbFailed(label, formatName(format));
    checkSize(header.width, header.height, label, maxPixels);
    return header;
}

// The stb format of `bytes` by its magic number, if any.
std::optional<ImageFileFormat> stbFormat(const std::string& bytes) {
    if (startsWith(bytes, "\x89PNG\r\n\x1a\n", 8)) return ImageFileFormat::Png;
    if (startsWith(bytes, "\xff\xd8\xff", 3)) return ImageFileFormat::Jpeg;
    if (startsWith(bytes, "#?RADIANCE", 10) || startsWith(bytes, "#?RGBE", 6)) return ImageFileFormat::Hdr;
    return std::nullopt;
}

[[noreturn]] void unsupportedFormat(const std::string& bytes, const std::string& label) {
    if (startsWith(bytes, kExrMagic, 4))
        throwInputError(label, "", "OpenEXR images are read from files only, not from memory");
    throwInputError(label, "", "unsupported image format (PNG, JPEG, Radiance HDR and OpenEXR are read)");
}

ImageFile decodeStb(const std::string& bytes, const std::string& label, ImageFileFormat format, ColorDecode decode,
                    uint64_t maxPixels, const AcceptImageSize& accept) {
    const char* what = formatName(format);
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const StbHeader header = readStbHeader(bytes, label, format, maxPixels);
    if (accept) accept(uint32_t(header.width), uint32_t(header.height));
    const int length = int(bytes.size());
    int w = header.width, h = header.height, n = header.channels;

    ImageFile image;
    image.width = uint32_t(w);
    image.height = uint32_t(h);
    image.format = format;
    image.channels = uint32_t(n);
    const size_t count = size_t(w) * size_t(h) * 4;
    if (format == ImageFileFormat::Jpeg) checkJpegSize(bytes, w, h, label);
    // Requesting 4 channels makes stb expand grey to RGB and add an opaque alpha.
    if (format == ImageFileFormat::Hdr) {
        checkHdrData(bytes, w, h, label);
        throwIfStopRequested();  // stb decodes in one call: a stop is seen before and after it
        std::unique_ptr<float, StbFree> pixels(stbi_loadf_from_memory(data, length, &w, &h, &n, 4));
        if (!pixels) stbFailed(label, what);
        // Allocated and written in one pass: resize would clear it first (512 MiB at 8k x 4k).
        image.rgba.assign(pixels.get(), pixels.get() + count);
    } else if (stbi_is_16_bit_from_memory(data, length)) {
        throwIfStopRequested();
        std::unique_ptr<stbi_us, StbFree> pixels(stbi_load_16_from_memory(data, length, &w, &h, &n, 4));
        if (!pixels) stbFailed(label, what);
        image.rgba.resize(count);
        for (size_t i = 0; i < count; ++i) image.rgba[i] = float(pixels.get()[i]) / 65535.0f;
    } else {
        throwIfStopRequested();
        std::unique_ptr<stbi_uc, StbFree> pixels(stbi_load_from_memory(data, length, &w, &h, &n, 4));
        if (!pixels) stbFailed(label, what);
        throwIfStopRequested();
        image.rgba.resize(count);
        // 256 entries: the decoded value of every code, computed once.
        float table[256];
        for (int c = 0; c < 256; ++c)
            table[c] = decode == ColorDecode::Srgb ? srgbToLinear(float(c) / 255.0f) : float(c) / 255.0f;
        for (size_t i = 0; i < count; ++i)
            image.rgba[i] = i % 4 == 3 ? float(pixels.get()[i]) / 255.0f : table[pixels.get()[i]];
        return image;
    }
    if (format != ImageFileFormat::Hdr && decode == ColorDecode::Srgb)
        for (size_t i = 0; i < count; ++i)
            if (i % 4 != 3) image.rgba[i] = srgbToLinear(image.rgba[i]);
    throwIfStopRequested();
    // Radiance HDR holds finite non-negative values by construction (RGBE); keep it so.
    for (float& v : image.rgba)
        if (!std::isfinite(v)) throwInputError(label, "", "image holds non-finite values");
    return image;
}

ImageFile decodeExrFile(const std::string& bytes, const std::string& label, uint64_t maxPixels,
                        const AcceptImageSize& accept) {
    ImageFile image;
    // Decoded straight into RGBA, its size refused from the header as for the other formats.
    const Image exr = decodeExrRgba(bytes, label, image.rgba, [&](uint32_t w, uint32_t h) {
        checkSize(w, h, label, maxPixels);
        if (accept) accept(w, h);
    });
    image.width = exr.width;
    image.height = exr.height;
    image.format = ImageFileFormat::Exr;
    image.channels = 3;
    throwIfStopRequested();
    for (size_t i = 0; i < image.rgba.size(); ++i)
        // EXR may hold NaN or infinity (half or float): data that would reach the
        // accumulation buffer as NaN, so it is bad input.
        if (i % 4 != 3 && !std::isfinite(image.rgba[i]))
            throwInputError(label, "", "image holds non-finite values (NaN or infinity)");
    return image;
}

}  // namespace

float srgbToLinear(float encoded) {
    // IEC 61966-2-1: linear segment below 0.04045, a 2.4 power curve above.
    const double x = encoded;
    return float(x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
}

ImageFile decodeImage(const std::string& bytes, const std::string& label, ColorDecode decode, uint64_t maxPixels,
                      const AcceptImageSize& accept) {
    const std::optional<ImageFileFormat> format = stbFormat(bytes);
    if (!format) unsupportedFormat(bytes, label);
    try {
        return decodeStb(bytes, label, *format, decode, maxPixels, accept);
    } catch (const std::bad_alloc&) {
        throwInputError(label, "", "image too large to load");
    }
}

std::pair<uint32_t, uint32_t> imageSize(const std::string& bytes, const std::string& label) {
    const std::optional<ImageFileFormat> format = stbFormat(bytes);
    if (!format) unsupportedFormat(bytes, label);
    const StbHeader header = readStbHeader(bytes, label, *format, kMaxImagePixels);
    return {uint32_t(header.width), uint32_t(header.height)};
}

ImageFile readImageFile(const std::filesystem::path& path, const std::string& label, ColorDecode decode,
                        uint64_t maxPixels, const AcceptImageSize& accept) {
    // These two refusals keep the words image files have always had; every other failure
    // to read is readInputFile's, as for any input file.
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throwInputError(label, "", "no such file");
    if (std::filesystem::is_directory(path, ec)) throwInputError(label, "", "is a directory, not an image");
    const std::string bytes = readInputFile(path, label, kMaxImageFileBytes);
    if (startsWith(bytes, kExrMagic, 4)) return decodeExrFile(bytes, label, maxPixels, accept);
    return decodeImage(bytes, label, decode, maxPixels, accept);
}

}  // namespace penumbra
