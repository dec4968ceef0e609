// Image files read as data (image/image_file.h): PNG (8 and 16 bit, grey and RGBA), JPEG,
// Radiance HDR and OpenEXR written here, read back texel by texel with row 0 at the top;
// the sRGB decoding curve; and the one-line refusals of missing, corrupt, unsupported and
// oversized files.
#include <cmath>
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "image/image_file.h"
#include "image/stb_image_write_static.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

fs::path dir(const std::string& name) { return test::freshOutputDir("image-file", name); }

void writeBytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

// The message of the InputError that reading `path` throws ("" when none).
std::string readError(const fs::path& path, ColorDecode decode = ColorDecode::Srgb) {
    try {
        readImageFile(path, decode);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// A 3x2 RGBA image whose every byte differs: a flipped, transposed or channel-swapped read shows.
std::vector<uint8_t> pattern8() {
    std::vector<uint8_t> p(3 * 2 * 4);
    for (size_t i = 0; i < p.size(); ++i) p[i] = uint8_t(10 * i + 3);
    return p;
}

}  // namespace

TEST(ImageFile, SrgbCurveMatchesTheStandard) {
    // IEC 61966-2-1: linear below 0.04045, ((x + 0.055) / 1.055)^2.4 above; ends fixed.
    EXPECT_FLOAT_EQ(srgbToLinear(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(srgbToLinear(1.0f), 1.0f);
    EXPECT_FLOAT_EQ(srgbToLinear(0.04f), 0.04f / 12.92f);
    EXPECT_NEAR(srgbToLinear(0.5f), 0.2140411f, 1e-6f);
    // The inverse of the PNG writer's encoding, code value by code value.
    for (int c = 0; c < 256; ++c) EXPECT_EQ(linearToSrgb8(srgbToLinear(float(c) / 255.0f)), c) << c;
}

TEST(ImageFile, Png8BitRgbaLinearAndSrgb) {
    fs::path file = dir("png8") / "t.png";
    std::vector<uint8_t> p = pattern8();
    ASSERT_TRUE(stbi_write_png(file.c_str(), 3, 2, 4, p.data(), 3 * 4));
    ImageFile linear = readImageFile(file, ColorDecode::Linear);
    ImageFile srgb = readImageFile(file, ColorDecode::Srgb);
    ASSERT_EQ(linear.width, 3u);
    ASSERT_EQ(linear.height, 2u);
    EXPECT_EQ(linear.format, ImageFileFormat::Png);
    EXPECT_EQ(linear.channels, 4u);
    for (uint32_t y = 0; y < 2; ++y)
        for (uint32_t x = 0; x < 3; ++x)
            for (int c = 0; c < 4; ++c) {
                float code = float(p[(y * 3 + x) * 4 + c]) / 255.0f;
                EXPECT_FLOAT_EQ(linear.texel(x, y)[c], code) << x << "," << y << "," << c;
                // Alpha is never sRGB-decoded.
                EXPECT_FLOAT_EQ(srgb.texel(x, y)[c], c == 3 ? code : srgbToLinear(code)) << x << "," << y << "," << c;
            }
}

TEST(ImageFile, GreyPngFillsRgbAndOpaqueAlpha) {
    fs::path file = dir("grey") / "g.png";
    const uint8_t grey[4] = {0, 64, 128, 255};
    ASSERT_TRUE(stbi_write_png(file.c_str(), 2, 2, 1, grey, 2));
    ImageFile image = readImageFile(file, ColorDecode::Linear);
    EXPECT_EQ(image.channels, 1u);
    for (uint32_t i = 0; i < 4; ++i) {
        const float* t = image.texel(i % 2, i / 2);
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(t[c], grey[i] / 255.0f);
        EXPECT_FLOAT_EQ(t[3], 1.0f);
    }
}

TEST(ImageFile, Png16Bit) {
    // stb_image_write has no 16-bit PNG: a minimal one is assembled here (stored zlib
    // block, CRCs computed), 2x1 grey 16-bit, values 0x1234 and 0xfedc.
    auto crc = [](const std::string& s) {
        uint32_t c = 0xffffffffu;
        for (unsigned char b : s) {
            c ^= b;
            for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
        }
        return c ^ 0xffffffffu;
    };
    auto be32 = [](uint32_t v) { return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; };
    auto chunk = [&](const std::string& type, const std::string& data) {
        return be32(uint32_t(data.size())) + type + data + be32(crc(type + data));
    };
    std::string ihdr = be32(2) + be32(1) + std::string{16, 0, 0, 0, 0};  // depth 16, grey
    std::string raw{0, char(0x12), char(0x34), char(0xfe), char(0xdc)};  // filter 0, two samples
    uint32_t a = 1, b = 0;
    for (unsigned char ch : raw) {
        a = (a + ch) % 65521;
        b = (b + a) % 65521;
    }
    std::string zlib = std::string{0x78, 0x01, 0x01, char(raw.size()), 0, char(~raw.size()), char(0xff)} + raw +
                       be32(b << 16 | a);
    std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", zlib) +
                      chunk("IEND", "");
    fs::path file = dir("png16") / "d.png";
    writeBytes(file, png);
    ImageFile image = readImageFile(file, ColorDecode::Linear);
    ASSERT_EQ(image.width, 2u);
    EXPECT_FLOAT_EQ(image.texel(0, 0)[0], float(0x1234) / 65535.0f);
    EXPECT_FLOAT_EQ(image.texel(1, 0)[2], float(0xfedc) / 65535.0f);
    ImageFile srgb = readImageFile(file, ColorDecode::Srgb);
    EXPECT_FLOAT_EQ(srgb.texel(1, 0)[1], srgbToLinear(float(0xfedc) / 65535.0f));
}

TEST(ImageFile, JpegDecodesNearTheWrittenColours) {
    // JPEG is lossy: a flat colour survives within a few code values.
    fs::path file = dir("jpeg") / "j.jpg";
    std::vector<uint8_t> rgb(16 * 16 * 3);
    for (size_t i = 0; i < rgb.size(); i += 3) {
        rgb[i] = 200;
        rgb[i + 1] = 100;
        rgb[i + 2] = 30;
    }
    ASSERT_TRUE(stbi_write_jpg(file.c_str(), 16, 16, 3, rgb.data(), 100));
    ImageFile image = readImageFile(file, ColorDecode::Linear);
    EXPECT_EQ(image.format, ImageFileFormat::Jpeg);
    ASSERT_EQ(image.width, 16u);
    EXPECT_NEAR(image.texel(7, 9)[0], 200 / 255.0f, 3 / 255.0f);
    EXPECT_NEAR(image.texel(7, 9)[1], 100 / 255.0f, 3 / 255.0f);
    EXPECT_NEAR(image.texel(7, 9)[2], 30 / 255.0f, 3 / 255.0f);
    EXPECT_NEAR(readImageFile(file, ColorDecode::Srgb).texel(3, 3)[0], srgbToLinear(200 / 255.0f), 0.02f);
}

TEST(ImageFile, HdrIsLinearAndNeverSrgbDecoded) {
    fs::path file = dir("hdr") / "h.hdr";
    // RGBE keeps 8 mantissa bits per channel: values with few bits survive exactly.
    const float rgb[2 * 2 * 3] = {1.0f, 2.0f, 4.0f, 0.5f, 0.25f, 8.0f, 16.0f, 0.125f, 1.5f, 3.0f, 6.0f, 12.0f};
    ASSERT_TRUE(stbi_write_hdr(file.c_str(), 2, 2, 3, rgb));
    for (ColorDecode decode : {ColorDecode::Linear, ColorDecode::Srgb}) {
        ImageFile image = readImageFile(file, decode);
        EXPECT_EQ(image.format, ImageFileFormat::Hdr);
        for (uint32_t i = 0; i < 4; ++i)
            for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(image.texel(i % 2, i / 2)[c], rgb[3 * i + c]) << i << "," << c;
    }
}

TEST(ImageFile, HdrDataThatEndsEarlyOrHasEmptyRunsIsRefusedNotHung) {
    // stb_image reads past the end of HDR pixel data as zeros, and loops forever on a
    // run-length encoded scanline whose run count is 0 (as a truncated file gives).
    fs::path d = dir("hdr-truncated");
    std::vector<float> rgb;
    for (int i = 0; i < 40 * 4 * 3; ++i) rgb.push_back(float((i * 37) % 11) * 0.25f + (i % 3 == 0 ? 0.0f : 0.5f));
    ASSERT_TRUE(stbi_write_hdr((d / "rle.hdr").c_str(), 40, 4, 3, rgb.data()));  // width >= 8: run-length encoded
    ASSERT_TRUE(stbi_write_hdr((d / "flat.hdr").c_str(), 4, 2, 3, rgb.data()));  // width < 8: flat
    std::ifstream in(d / "rle.hdr", std::ios::binary);
    std::string rle((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ifstream inFlat(d / "flat.hdr", std::ios::binary);
    std::string flat((std::istreambuf_iterator<char>(inFlat)), std::istreambuf_iterator<char>());
    // The whole files read, with their values.
    ImageFile whole = readImageFile(d / "rle.hdr", ColorDecode::Linear);
    EXPECT_FLOAT_EQ(whole.texel(39, 3)[1], rgb[(3 * 40 + 39) * 3 + 1]);
    EXPECT_EQ(readImageFile(d / "flat.hdr", ColorDecode::Linear).width, 4u);
    // Cut anywhere in the pixel data: refused, never hung.
    size_t header = rle.find("+X 40\n") + 6;
    for (size_t cut : {header, header + 1, header + 4, header + 5, (header + rle.size()) / 2, rle.size() - 1}) {
        writeBytes(d / "cut.hdr", rle.substr(0, cut));
        std::string error = readError(d / "cut.hdr");
        EXPECT_NE(error.find("cut.hdr: cannot decode HDR image"), std::string::npos)
            << "cut at " << cut << ": " << error;
    }
    writeBytes(d / "cut-flat.hdr", flat.substr(0, flat.size() - 3));
    EXPECT_NE(readError(d / "cut-flat.hdr").find("pixel data ends early"), std::string::npos);
    // A run count of 0 in a whole file.
    std::string empty = rle;
    empty[header + 4] = 0;
    writeBytes(d / "empty-run.hdr", empty);
    EXPECT_NE(readError(d / "empty-run.hdr").find("bad run length"), std::string::npos);
}

TEST(ImageFile, ExrIsLinearWithRowZeroAtTheTop) {
    fs::path file = dir("exr") / "e.exr";
    Image exr;
    exr.width = 2;
    exr.height = 3;
    for (int i = 0; i < 18; ++i) exr.rgb.push_back(0.37f * float(i) + 0.01f);
    writeExr(file, exr);
    ImageFile image = readImageFile(file, ColorDecode::Srgb);
    EXPECT_EQ(image.format, ImageFileFormat::Exr);
    ASSERT_EQ(image.height, 3u);
    for (uint32_t y = 0; y < 3; ++y)
        for (uint32_t x = 0; x < 2; ++x) {
            for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(image.texel(x, y)[c], exr.pixel(x, y)[c]);
            EXPECT_FLOAT_EQ(image.texel(x, y)[3], 1.0f);
        }
}

TEST(ImageFile, ExrWithNonFiniteValuesIsRefused) {
    fs::path file = dir("exr-nan") / "nan.exr";
    Image exr;
    exr.width = exr.height = 1;
    exr.rgb = {1.0f, std::nanf(""), 0.0f};
    writeExr(file, exr);
    std::string error = readError(file);
    EXPECT_NE(error.find("nan.exr: image holds non-finite values"), std::string::npos) << error;
}

TEST(ImageFile, BadFilesGiveOneLineErrorsNamingTheFile) {
    fs::path d = dir("bad");
    std::vector<uint8_t> p = pattern8();
    ASSERT_TRUE(stbi_write_png((d / "good.png").c_str(), 3, 2, 4, p.data(), 12));
    std::ifstream in(d / "good.png", std::ios::binary);
    std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    writeBytes(d / "truncated.png", png.substr(0, png.size() / 2));
    std::string corrupt = png;
    for (size_t i = 40; i < corrupt.size() - 12; ++i) corrupt[i] = char(0x5a);
    writeBytes(d / "corrupt.png", corrupt);
    writeBytes(d / "picture.bmp", std::string("BM\x36\0\0\0\0\0\0\0\x36\0\0\0", 14));
    writeBytes(d / "empty.png", "");
    fs::create_directories(d / "folder.png");
    // A PNG header claiming 100000 x 100000 pixels: refused from the header alone.
    std::string huge = png;
    auto be32 = [](uint32_t v) { return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; };
    huge.replace(16, 8, be32(100000) + be32(100000));
    writeBytes(d / "huge.png", huge);
    // Each side within 16384 but 81M pixels in all (grey: under stb_image's own 2^30-byte cap).
    huge.replace(16, 10, be32(9000) + be32(9000) + std::string{8, 0});
    writeBytes(d / "huge-area.png", huge);
    std::string hugeHdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 20000 +X 20000\n";
    writeBytes(d / "huge.hdr", hugeHdr);

    struct Case {
        const char* file;
        const char* expected;
    };
    for (Case c : {Case{"missing.png", "missing.png: no such file"},
                   Case{"truncated.png", "truncated.png: cannot decode PNG image"},
                   Case{"corrupt.png", "corrupt.png: cannot decode PNG image"},
                   Case{"picture.bmp", "picture.bmp: unsupported image format"},
                   Case{"empty.png", "empty.png: unsupported image format"},
                   Case{"folder.png", "folder.png: is a directory"}, Case{"huge.png", "huge.png: "},
                   Case{"huge-area.png", "huge-area.png: image is 9000x9000, larger than the limit"},
                   Case{"huge.hdr", "huge.hdr: "}}) {
        std::string error = readError(d / c.file);
        EXPECT_NE(error.find(c.expected), std::string::npos) << c.file << ": " << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    }
    // Sides beyond 16384 are refused from the header, by stb_image's own limit (PNG) or ours.
    for (const char* f : {"huge.png", "huge.hdr"}) {
        std::string error = readError(d / f);
        bool sized = error.find(": too large") != std::string::npos ||
                     error.find("larger than the limit") != std::string::npos;
        EXPECT_TRUE(sized) << error;
    }
    // The label replaces the path in messages.
    try {
        readImageFile(d / "picture.bmp", "textures/picture.bmp", ColorDecode::Srgb);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("textures/picture.bmp: ", 0), 0u) << e.what();
    }
}
