// Host images: EXR round trips and atomic writes, readExr's one-line InputErrors on bad
// files, the sRGB PNG encoding, spp-weighted merging and its refusals, compare metrics.
// Each test works in its own folder under build/test-output/ (CTest runs them in parallel).
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "gpu_fixture.h"
#include "image/atomic_file.h"
#include "image/image.h"

#include "png_reader.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

// An empty folder of its own for one test.
fs::path freshDir(const std::string& test) {
    fs::path dir = test::outputPath("image-" + test);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// Values with full float mantissas, so a lossy path (half, rounding) would show.
Image noiseImage(uint32_t width, uint32_t height, uint32_t seed) {
    Image image;
    image.width = width;
    image.height = height;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(0.0f, 10.0f);
    image.rgb.resize(size_t(width) * height * 3);
    for (float& v : image.rgb) v = value(rng);
    return image;
}

Image constantImage(uint32_t width, uint32_t height, float value, std::optional<int> spp) {
    Image image;
    image.width = width;
    image.height = height;
    image.rgb.assign(size_t(width) * height * 3, value);
    image.meta.spp = spp;
    return image;
}

std::string readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

void writeBytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

size_t fileCount(const fs::path& dir) { return size_t(std::distance(fs::directory_iterator(dir), {})); }

// Runs f, expecting an InputError whose one-line message contains `needle`.
template <class F>
void expectInputError(F&& f, const std::string& needle) {
    try {
        f();
        ADD_FAILURE() << "no InputError thrown (expected one mentioning " << needle << ")";
    } catch (const InputError& e) {
        std::string message = e.what();
        EXPECT_NE(message.find(needle), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected InputError, got: " << e.what();
    }
}

}  // namespace

// ---------------------------------------------------------------------------- EXR

TEST(ImageExr, RoundTripIsBitExactWithAllAttributes) {
    const fs::path dir = freshDir("roundtrip-all");
    Image image = noiseImage(37, 23, 1);
    image.rgb[5] = -3.5f;  // negative and special values pass through a float EXR unchanged
    image.rgb[7] = std::numeric_limits<float>::infinity();
    image.rgb[8] = 1e-30f;
    image.meta = {64, 7, 128, R"({"type":"direct","strategy":"mis"})", 12.625, "sobol"};
    writeExr(dir / "all.exr", image);

    const Image back = readExr(dir / "all.exr");
    ASSERT_EQ(back.width, 37u);
    ASSERT_EQ(back.height, 23u);
    ASSERT_EQ(back.rgb.size(), image.rgb.size());
    EXPECT_EQ(std::memcmp(back.rgb.data(), image.rgb.data(), image.rgb.size() * sizeof(float)), 0);
    EXPECT_EQ(back.meta.spp, 64);
    EXPECT_EQ(back.meta.seed, 7);
    EXPECT_EQ(back.meta.sampleOffset, 128);
    EXPECT_EQ(back.meta.integrator, image.meta.integrator);
    EXPECT_EQ(back.meta.renderSeconds, 12.625);
    EXPECT_EQ(back.meta.sampler, "sobol");
    EXPECT_EQ(fileCount(dir), 1u) << "a temporary file was left behind";
}

TEST(ImageExr, RoundTripWithoutAttributes) {
    const fs::path dir = freshDir("roundtrip-none");
    const Image image = noiseImage(5, 9, 2);
    writeExr(dir / "none.exr", image);
    writeExr(dir / "none.exr", image);  // overwriting an existing file is fine
    const Image back = readExr(dir / "none.exr");
    ASSERT_EQ(back.width, 5u);
    ASSERT_EQ(back.height, 9u);
    EXPECT_EQ(back.rgb, image.rgb);
    EXPECT_FALSE(back.meta.spp || back.meta.seed || back.meta.sampleOffset || back.meta.integrator ||
                 back.meta.renderSeconds || back.meta.sampler);
    EXPECT_EQ(fileCount(dir), 1u) << "a temporary file was left behind";
}

TEST(ImageExr, TopRowIsPixelZero) {
    const fs::path dir = freshDir("orientation");
    Image image = constantImage(2, 3, 0.0f, std::nullopt);
    image.pixel(1, 0)[1] = 1.0f;  // top right, green
    writeExr(dir / "o.exr", image);
    const Image back = readExr(dir / "o.exr");
    EXPECT_EQ(back.pixel(1, 0)[1], 1.0f);
    EXPECT_EQ(back.pixel(1, 2)[1], 0.0f);
}

TEST(ImageExr, WriteIntoMissingDirectoryThrowsAndLeavesNothing) {
    const fs::path dir = freshDir("missing-dir");
    const fs::path target = dir / "no-such-dir" / "out.exr";
    try {
        writeExr(target, noiseImage(4, 4, 3));
        FAIL() << "writeExr succeeded";
    } catch (const InputError& e) {
        FAIL() << "cannot write the output is exit 1, not an InputError: " << e.what();
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("failed to write " + target.string()), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(target));
    EXPECT_EQ(fileCount(dir), 0u);
}

TEST(ImageExr, FailedWriteRemovesTemporary) {
    // The target is a directory: the temporary can be written but not renamed over it
    // (or the writer refuses up front); either way nothing new may remain.
    const fs::path dir = freshDir("failed-rename");
    fs::create_directories(dir / "taken.exr");
    EXPECT_THROW(writeExr(dir / "taken.exr", noiseImage(4, 4, 4)), std::runtime_error);
    EXPECT_EQ(fileCount(dir), 1u);
    EXPECT_TRUE(fs::is_directory(dir / "taken.exr"));
}

TEST(ImageAtomicFile, WriterFailureRemovesTemporaryAndKeepsOldFile) {
    // A writer that fails halfway (disk full, interrupted encoder) after creating the
    // temporary: the temporary goes, an earlier complete file stays as it was.
    const fs::path dir = freshDir("atomic");
    writeBytes(dir / "out.bin", "old");
    try {
        writeFileAtomically(dir / "out.bin", [](const fs::path& tmp) {
            writeBytes(tmp, "half");
            throw std::runtime_error("disk full");
        });
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "failed to write " + (dir / "out.bin").string() + ": disk full");
    }
    EXPECT_EQ(fileCount(dir), 1u);
    EXPECT_EQ(readBytes(dir / "out.bin"), "old");
}

TEST(ImageExr, ReadsHalfChannelsAndOffsetDataWindow) {
    // Written with OpenEXR directly: half R, G, B plus an unrelated channel A, data window
    // (10, 20)-(12, 21), an unexpected type for penumbra:spp (string: must read as absent).
    const fs::path dir = freshDir("half-offset");
    const fs::path path = dir / "half.exr";
    const Imath::Box2i window({10, 20}, {12, 21});
    Imf::Header header(Imath::Box2i({0, 0}, {15, 25}), window);
    for (const char* c : {"R", "G", "B", "A"}) header.channels().insert(c, Imf::Channel(Imf::HALF));
    header.insert("penumbra:spp", Imf::StringAttribute("sixteen"));
    std::vector<half> data(3 * 2 * 4);
    for (size_t i = 0; i < data.size(); ++i) data[i] = half(0.25f * float(i));  // exact in half
    {
        Imf::FrameBuffer frame;
        const char* channels[4] = {"R", "G", "B", "A"};
        for (int c = 0; c < 4; ++c)
            frame.insert(channels[c], Imf::Slice::Make(Imf::HALF, data.data() + c, window, 4 * sizeof(half),
                                                       3 * 4 * sizeof(half)));
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(2);
    }
    const Image image = readExr(path);
    ASSERT_EQ(image.width, 3u);
    ASSERT_EQ(image.height, 2u);
    for (uint32_t y = 0; y < 2; ++y)
        for (uint32_t x = 0; x < 3; ++x)
            for (int c = 0; c < 3; ++c) EXPECT_EQ(image.pixel(x, y)[c], 0.25f * float((y * 3 + x) * 4 + c));
    EXPECT_FALSE(image.meta.spp);
}

TEST(ImageExr, MissingChannelIsInputError) {
    const fs::path dir = freshDir("missing-channel");
    const fs::path path = dir / "luminance.exr";
    Imf::Header header(2, 2);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    std::vector<float> y(4, 1.0f);
    {
        Imf::FrameBuffer frame;
        frame.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y.data()), sizeof(float), 2 * sizeof(float)));
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(2);
    }
    expectInputError([&] { readExr(path); }, path.string() + ": missing channel R");
}

TEST(ImageExr, MissingGarbageAndDirectoryAreInputErrors) {
    const fs::path dir = freshDir("bad-files");
    expectInputError([&] { readExr(dir / "absent.exr"); }, (dir / "absent.exr").string() + ": ");
    writeBytes(dir / "garbage.exr", "this is not an image at all, just some text\n");
    expectInputError([&] { readExr(dir / "garbage.exr"); }, (dir / "garbage.exr").string() + ": ");
    writeBytes(dir / "empty.exr", "");
    expectInputError([&] { readExr(dir / "empty.exr"); }, (dir / "empty.exr").string() + ": ");
    expectInputError([&] { readExr(dir); }, dir.string() + ": ");
}

TEST(ImageExr, TruncatedFilesAreInputErrors) {
    // Cut a valid file at every point of the header and at a spread of points in the
    // pixel data: each must fail cleanly, never crash or return a partial image.
    const fs::path dir = freshDir("truncated");
    Image image = noiseImage(64, 48, 5);
    image.meta = {16, 1, 0, R"({"type":"ao"})", 1.5};
    writeExr(dir / "full.exr", image);
    const std::string bytes = readBytes(dir / "full.exr");
    ASSERT_GT(bytes.size(), 1000u);
    std::vector<size_t> cuts;
    for (size_t n = 0; n < 600; n += 7) cuts.push_back(n);
    for (size_t n = 600; n < bytes.size(); n += bytes.size() / 23) cuts.push_back(n);
    cuts.push_back(bytes.size() - 1);
    const fs::path cut = dir / "cut.exr";
    for (size_t n : cuts) {
        SCOPED_TRACE("truncated to " + std::to_string(n) + " of " + std::to_string(bytes.size()) + " bytes");
        writeBytes(cut, bytes.substr(0, n));
        expectInputError([&] { readExr(cut); }, cut.string() + ": ");
    }
}

// The bytes of `image` as writeExr writes it, to dir/full.exr.
std::string writtenExr(const fs::path& dir, const Image& image) {
    writeExr(dir / "full.exr", image);
    return readBytes(dir / "full.exr");
}

TEST(ImageExr, DecodesFromMemoryAsFromTheFile) {
    // The bytes writeExr wrote, decoded from memory, give the file's image exactly: every
    // pixel (67 x 45: several 16-line ZIP chunks, a width that is no power of two) and
    // every penumbra:* attribute.
    const fs::path dir = freshDir("memory");
    Image image = noiseImage(67, 45, 11);
    image.meta = {16, 3, 32, R"({"type":"direct"})", 2.25, "sobol", std::vector<SamplePiece>{{3, 0, 16}, {3, 32, 48}}};
    const Image fromMemory = decodeExr(writtenExr(dir, image), "memory.exr");
    const Image fromFile = readExr(dir / "full.exr");
    ASSERT_EQ(fromMemory.width, fromFile.width);
    ASSERT_EQ(fromMemory.height, fromFile.height);
    EXPECT_EQ(fromMemory.rgb, fromFile.rgb);
    EXPECT_EQ(fromMemory.rgb, image.rgb);  // and both are what was written (32-bit float, lossless)
    EXPECT_EQ(fromMemory.meta.spp, fromFile.meta.spp);
    EXPECT_EQ(fromMemory.meta.seed, fromFile.meta.seed);
    EXPECT_EQ(fromMemory.meta.sampleOffset, fromFile.meta.sampleOffset);
    EXPECT_EQ(fromMemory.meta.integrator, fromFile.meta.integrator);
    EXPECT_EQ(fromMemory.meta.renderSeconds, fromFile.meta.renderSeconds);
    EXPECT_EQ(fromMemory.meta.sampler, fromFile.meta.sampler);
    EXPECT_EQ(fromMemory.meta.pieces, fromFile.meta.pieces);
    EXPECT_EQ(fromMemory.meta.pieces, image.meta.pieces);
}

TEST(ImageExr, TruncatedBytesInMemoryAreInputErrors) {
    // Every prefix of a valid file, empty to all but the last byte, decoded from memory:
    // each is one InputError naming the given name, never a crash, a read past the bytes
    // or a partial image.
    Image image = noiseImage(19, 37, 13);
    image.meta = {4, 1, 0, R"({"type":"ao"})", 0.5};
    const std::string bytes = writtenExr(freshDir("memory-truncated"), image);
    ASSERT_GT(bytes.size(), 1000u);
    for (size_t n = 0; n < bytes.size(); ++n) {
        SCOPED_TRACE("truncated to " + std::to_string(n) + " of " + std::to_string(bytes.size()) + " bytes");
        expectInputError([&] { decodeExr(std::string_view(bytes).substr(0, n), "memory.exr"); }, "memory.exr: ");
        if (HasFailure()) break;  // one failing length says it; thousands would drown it
    }
}

// A smooth image, so ZIP really deflates it: OpenEXR stores incompressible chunks raw,
// and raw float data has no checksum that could reveal a corruption.
Image smoothImage() {
    Image image = constantImage(64, 48, 0.0f, 16);
    for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = float(i % 192) * 0.5f;
    image.meta.seed = 1;
    image.meta.integrator = R"({"type":"ao"})";
    return image;
}

TEST(ImageExr, CorruptPixelDataIsInputError) {
    // Overwrites part of the deflated pixel data; zlib's checksum notices.
    const fs::path dir = freshDir("corrupt");
    writeExr(dir / "full.exr", smoothImage());
    std::string bytes = readBytes(dir / "full.exr");
    for (size_t i = bytes.size() / 2; i < bytes.size() / 2 + 64; ++i) bytes[i] = char(0x5a ^ i);
    writeBytes(dir / "corrupt.exr", bytes);
    expectInputError([&] { readExr(dir / "corrupt.exr"); }, (dir / "corrupt.exr").string() + ": ");
}

TEST(ImageExr, HugeAttributeSizeIsRefusedUpFront) {
    // The integrator string's size field set to 0x7f00000d: OpenEXR alone would allocate
    // 2 GB before noticing the file is 2 kB.
    const fs::path dir = freshDir("huge-attribute");
    writeExr(dir / "full.exr", smoothImage());
    std::string bytes = readBytes(dir / "full.exr");
    const size_t at = bytes.find("penumbra:integrator");
    ASSERT_NE(at, std::string::npos);
    const size_t sizeField = at + std::strlen("penumbra:integrator") + 1 + std::strlen("string") + 1;
    ASSERT_EQ(bytes[sizeField], 13);
    bytes[sizeField + 3] = 0x7f;
    writeBytes(dir / "huge.exr", bytes);
    expectInputError([&] { readExr(dir / "huge.exr"); }, "attribute \"penumbra:integrator\" claims");
}

TEST(ImageExr, SingleByteCorruptionsNeverCrash) {
    // Every byte of the header and offset table, and a spread of pixel-data bytes, set to
    // 0x7f and to its bit-flipped self: each read either succeeds (the byte was a pixel
    // or an unchecked value) or throws InputError; nothing else, and no crash.
    const fs::path dir = freshDir("fuzz");
    writeExr(dir / "full.exr", smoothImage());
    const std::string bytes = readBytes(dir / "full.exr");
    const size_t headerEnd = bytes.find("penumbra:spp") + 64;  // past the last attribute and the offsets
    ASSERT_LT(headerEnd, bytes.size());
    const fs::path path = dir / "mutant.exr";
    for (size_t pos = 0; pos < bytes.size(); pos += pos < headerEnd ? 1 : 13) {
        for (int mode = 0; mode < 2; ++mode) {
            std::string mutant = bytes;
            mutant[pos] = mode == 0 ? char(0x7f) : char(mutant[pos] ^ (1 << (pos % 8)));
            writeBytes(path, mutant);
            try {
                const Image image = readExr(path);
                EXPECT_EQ(image.rgb.size(), size_t(image.width) * image.height * 3);
            } catch (const InputError&) {
            } catch (const std::exception& e) {
                ADD_FAILURE() << "byte " << pos << " mode " << mode << ": not an InputError: " << e.what();
            }
        }
    }
}

// ---------------------------------------------------------------------------- PNG

TEST(ImagePng, LinearToSrgb8KnownValues) {
    // 0.0031308 is the linear segment's end: 12.92 * 0.0031308 * 255 = 10.31 -> 10.
    // 0.5: 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357, * 255 = 187.52 -> 188.
    EXPECT_EQ(linearToSrgb8(0.0f), 0);
    EXPECT_EQ(linearToSrgb8(0.0031308f), 10);
    EXPECT_EQ(linearToSrgb8(0.5f), 188);
    EXPECT_EQ(linearToSrgb8(1.0f), 255);
    EXPECT_EQ(linearToSrgb8(2.0f), 255);
    EXPECT_EQ(linearToSrgb8(-1.0f), 0);
    EXPECT_EQ(linearToSrgb8(std::nanf("")), 0);
    EXPECT_EQ(linearToSrgb8(std::numeric_limits<float>::infinity()), 255);
    // 18% grey: 1.055 * 0.18^(1/2.4) - 0.055 = 0.461356, * 255 = 117.65 -> 118.
    EXPECT_EQ(linearToSrgb8(0.18f), 118);
    // Monotonic over the whole range: a tone map must never invert brightness.
    uint8_t previous = 0;
    for (int i = 0; i <= 10000; ++i) {
        const uint8_t v = linearToSrgb8(float(i) / 10000.0f);
        ASSERT_GE(v, previous) << "at " << i;
        previous = v;
    }
}

TEST(ImagePng, WrittenPixelsReadBack) {
    const fs::path dir = freshDir("png");
    const float values[6] = {0.0f, 0.0031308f, 0.5f, 1.0f, 2.0f, std::nanf("")};
    const uint8_t expected[6] = {0, 10, 188, 255, 255, 0};
    Image image = constantImage(6, 2, 0.0f, std::nullopt);
    for (uint32_t x = 0; x < 6; ++x) {
        for (int c = 0; c < 3; ++c) {
            image.pixel(x, 0)[c] = values[x];
            image.pixel(x, 1)[c] = values[x] * 0.5f;  // exposure +1 below brings these back up
        }
    }
    image.pixel(0, 0)[0] = 1.0f;  // channel order: a red top-left pixel stays red
    writePng(dir / "plain.png", image);
    writePng(dir / "exposed.png", image, {.exposure = 1.0f});
    EXPECT_EQ(fileCount(dir), 2u) << "a temporary file was left behind";

    for (const char* name : {"plain.png", "exposed.png"}) {
        SCOPED_TRACE(name);
        test::Png png = test::readPng(dir / name, 0);
        const uint8_t* pixels = png.pixels.data();
        ASSERT_EQ(png.width, 6);
        ASSERT_EQ(png.height, 2);
        ASSERT_EQ(png.channelsInFile, 3);
        const bool exposed = std::string(name) == "exposed.png";
        for (int x = 0; x < 6; ++x) {
            for (int c = 0; c < 3; ++c) {
                const int top = x == 0 && c == 0 ? 255 : expected[x];
                EXPECT_EQ(pixels[(0 * 6 + x) * 3 + c], exposed ? linearToSrgb8(image.pixel(x, 0)[c] * 2.0f) : top)
                    << "top x=" << x << " c=" << c;
                EXPECT_EQ(pixels[(1 * 6 + x) * 3 + c], exposed ? expected[x] : linearToSrgb8(image.pixel(x, 1)[c]))
                    << "bottom x=" << x << " c=" << c;
            }
        }
    }
}

TEST(ImagePng, WriteIntoMissingDirectoryThrows) {
    const fs::path dir = freshDir("png-missing-dir");
    EXPECT_THROW(writePng(dir / "nope" / "out.png", constantImage(2, 2, 0.5f, std::nullopt)), std::runtime_error);
    EXPECT_EQ(fileCount(dir), 0u);
}

// ---------------------------------------------------------------------------- merge

TEST(ImageMerge, WeightsBySpp) {
    // 3 spp of value 1 and 1 spp of value 5: (3*1 + 1*5) / 4 = 2, with spp 4.
    Image a = constantImage(3, 2, 1.0f, 3), b = constantImage(3, 2, 5.0f, 1);
    a.meta.seed = 9;
    a.meta.sampleOffset = 4;
    a.meta.integrator = R"({"type":"ao"})";
    a.meta.renderSeconds = 1.5;
    b.meta.seed = 9;
    b.meta.sampleOffset = 0;  // [0, 1) and [4, 7): disjoint, so the same seed is fine
    b.meta.integrator = a.meta.integrator;
    b.meta.renderSeconds = 2.25;
    const Image m = mergeImages({a, b}, {"a.exr", "b.exr"});
    ASSERT_EQ(m.width, 3u);
    ASSERT_EQ(m.height, 2u);
    for (float v : m.rgb) EXPECT_EQ(v, 2.0f);
    EXPECT_EQ(m.meta.spp, 4);
    EXPECT_EQ(m.meta.seed, 9);
    EXPECT_EQ(m.meta.sampleOffset, 0);
    EXPECT_EQ(m.meta.integrator, a.meta.integrator);
    EXPECT_EQ(m.meta.renderSeconds, 3.75);
}

TEST(ImageMerge, SingleImageMergesToItself) {
    Image a = noiseImage(4, 3, 7);
    a.meta.spp = 7;
    const Image m = mergeImages({a}, {"a.exr"});
    EXPECT_EQ(m.rgb, a.rgb);
    EXPECT_EQ(m.meta.spp, 7);
}

TEST(ImageMerge, DifferentSeedsMayShareSampleIndices) {
    Image a = constantImage(1, 1, 2.0f, 4), b = constantImage(1, 1, 4.0f, 4);
    a.meta.seed = 1;
    b.meta.seed = 2;
    EXPECT_EQ(mergeImages({a, b}, {"a.exr", "b.exr"}).rgb[0], 3.0f);
}

TEST(ImageMerge, RefusesInputsWhoseMeanIsNotAnEstimate) {
    const Image good = constantImage(4, 4, 1.0f, 8);
    expectInputError([&] { mergeImages({good, constantImage(4, 4, 1.0f, std::nullopt)}, {"a.exr", "b.exr"}); },
                     "b.exr: missing penumbra:spp attribute; only penumbra renders can be merged");
    expectInputError([&] { mergeImages({good, constantImage(4, 5, 1.0f, 8)}, {"a.exr", "b.exr"}); },
                     "b.exr: size 4x5 differs from a.exr (4x4)");

    Image a = good, b = good;
    a.meta.seed = b.meta.seed = 3;
    a.meta.sampleOffset = 0;  // [0, 8)
    b.meta.sampleOffset = 6;  // [6, 14): indices 6 and 7 were used twice
    expectInputError([&] { mergeImages({a, b}, {"a.exr", "b.exr"}); }, "b.exr: sample indices [6, 8) overlap with a.exr");
    b.meta.sampleOffset = 8;
    EXPECT_NO_THROW(mergeImages({a, b}, {"a.exr", "b.exr"}));
    a.meta.sampleOffset.reset();  // absent means the default offset, 0
    b.meta.sampleOffset.reset();
    expectInputError([&] { mergeImages({a, b}, {"a.exr", "b.exr"}); }, "overlap with a.exr");

    Image c = good, d = good;
    c.meta.integrator = R"({"type":"ao"})";
    d.meta.integrator = R"({"type":"direct"})";
    expectInputError([&] { mergeImages({c, d}, {"c.exr", "d.exr"}); },
                     "merging renders of different integrators is not meaningful");
    expectInputError([&] { mergeImages({c, d}, {"c.exr", "d.exr"}); }, "d.exr: ");

    EXPECT_THROW(mergeImages({}, {}), InputError);
}

TEST(ImageMerge, PartialsMustShareTheSampler) {
    // Different seeds, so only the sampler stands in the way.
    Image a = constantImage(2, 2, 1.0f, 4), b = constantImage(2, 2, 3.0f, 4);
    a.meta.seed = 1;
    b.meta.seed = 2;
    a.meta.sampler = "sobol";
    b.meta.sampler = "independent";
    expectInputError([&] { mergeImages({a, b}, {"a.exr", "b.exr"}); },
                     "b.exr: sampler independent differs from a.exr's (sobol)");
    // A render without the attribute predates the option and used independent samples.
    b.meta.sampler.reset();
    expectInputError([&] { mergeImages({a, b}, {"a.exr", "b.exr"}); }, "sampler independent differs");
    a.meta.sampler = "independent";
    EXPECT_EQ(mergeImages({a, b}, {"a.exr", "b.exr"}).rgb[0], 2.0f);
    b.meta.sampler = a.meta.sampler = "sobol";
    const Image m = mergeImages({a, b}, {"a.exr", "b.exr"});
    EXPECT_EQ(m.meta.sampler, "sobol");
}

// ---------------------------------------------------------------------------- compare

TEST(ImageCompare, HandComputedMetrics) {
    // a = (1,2,3), (0,0,0); b = (1,1,1), (0,0,1). Differences 0,1,2,0,0,-1 over 6 values:
    //   rmse    = sqrt((0+1+4+0+0+1)/6) = 1
    //   relmse  = (1/(1+0.01) + 4/(1+0.01) + 1/(1+0.01)) / 6 = 1/1.01
    //   mean_a  = 6/6 = 1,  mean_b = 4/6,  max_abs = 2
    Image a = constantImage(2, 1, 0.0f, std::nullopt), b = a;
    a.rgb = {1, 2, 3, 0, 0, 0};
    b.rgb = {1, 1, 1, 0, 0, 1};
    const CompareMetrics m = compareImages(a, b);
    EXPECT_DOUBLE_EQ(m.rmse, 1.0);
    EXPECT_DOUBLE_EQ(m.relmse, 1.0 / 1.01);
    EXPECT_DOUBLE_EQ(m.meanA, 1.0);
    EXPECT_DOUBLE_EQ(m.meanB, 4.0 / 6.0);
    EXPECT_DOUBLE_EQ(m.maxAbs, 2.0);

    // relmse divides by the reference b: a dark reference pixel weighs more.
    // a = 0.1 everywhere, b = 0: (0.01 / 0.01) = 1 per value.
    const CompareMetrics dark = compareImages(constantImage(1, 1, 0.1f, std::nullopt),
                                              constantImage(1, 1, 0.0f, std::nullopt));
    EXPECT_NEAR(dark.relmse, 1.0, 1e-6);

    const CompareMetrics same = compareImages(a, a);
    EXPECT_EQ(same.rmse, 0.0);
    EXPECT_EQ(same.relmse, 0.0);
    EXPECT_EQ(same.maxAbs, 0.0);
}

TEST(ImageCompare, SizeMismatchIsInputError) {
    const Image a = constantImage(2, 2, 0.0f, std::nullopt), b = constantImage(2, 3, 0.0f, std::nullopt);
    EXPECT_THROW(compareImages(a, b), InputError);
    expectInputError([&] { compareImages(a, b, "a.exr", "b.exr"); }, "a.exr: size 2x2 differs from b.exr (2x3)");
}
