// Hostile inputs against the image readers, job files and merge (docs/design/contract-decisions.md, "input rules"):
// each case once hung the program, exhausted its memory or gave a wrong result. Those that
// could hang or grow run `penumbra` as a child under a time and memory limit
// (runPenumbraBounded), so that a regression fails here instead of stalling the test run.
#include <cmath>
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "gltf_builder.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "image/image_file.h"
#include "render_helpers.h"
#include "scene/load.h"
#include "scene_test_util.h"

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

void writeBytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

// A scene of one quad whose albedo is the texture `texture` (relative to the scene).
fs::path writeTexturedScene(const fs::path& dir, const std::string& texture) {
    json doc = {
        {"materials", {{"m", {{"type", "diffuse"}, {"albedo", {{"texture", texture}}}}}}},
        {"shapes",
         {{{"type", "quad"}, {"origin", {0, 0, 0}}, {"edge_u", {1, 0, 0}}, {"edge_v", {0, 0, 1}}, {"material", "m"}}}},
        {"film", {{"width", 4}, {"height", 4}}},
        {"sampler", {{"spp", 1}}}};
    return penumbra::test::writeFile(dir / "scene.json", doc.dump());
}

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

}  // namespace

TEST(HostileInputs, HdrHeaderLineStartingWithNulIsRefusedNotHung) {
    // stb_image ends an HDR header at a line that starts with a NUL byte, so its pixel data
    // starts after the next line ("-Y 1 +X 16"): a run-length encoded scanline whose first
    // channel is a literal run of 16 that the file ends inside, after which stb reads zeros,
    // runs of length 0, forever. The 15 bytes it swallows are "\n\n", an empty line and a
    // valid scanline (runs of 16): what a check that looks for the first empty line found.
    const std::string valid = std::string("\x02\x02\x00\x10", 4) + std::string("\x90\x01\x90\x01\x90\x01\x90\x80", 8);
    const std::string hdr = std::string("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\0\n-Y 1 +X 16\n", 47) +
                            std::string("\x02\x02\x00\x10\x10", 5) + "\n\n\n" + valid;
    fs::path dir = penumbra::test::freshTempDir();
    writeBytes(dir / "nul.hdr", hdr);
    fs::path scene = writeTexturedScene(dir, "nul.hdr");
    std::string err;
    int status = penumbra::test::runPenumbraBounded(
        "render " + quoted(scene) + " -o " + quoted(dir / "out.exr") + " --quiet", 10, 2048, &err);
    EXPECT_EQ(status, 2) << err;
    EXPECT_NE(err.find("nul.hdr: cannot decode HDR image: "), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
}

namespace {

// A glTF model of one quad and `images.size()` materials, material i textured by image i
// (each image object as given).
std::string modelWithImages(const std::vector<json>& images) {
    penumbra::test::GltfBuilder b;
    json primitive = {{"attributes", {{"POSITION", b.positions({-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1})}}},
                      {"indices", b.indices({0, 2, 1, 0, 3, 2})},
                      {"material", 0}};
    b.addMeshNode(primitive);
    for (size_t i = 0; i < images.size(); ++i) {
        b.doc["materials"].push_back({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", i}}}}}});
        b.doc["textures"].push_back({{"source", i}});
        b.doc["images"].push_back(images[i]);
    }
    return b.gltf();
}

// The first bytes of a PNG of `width` x `height` (8-bit RGB): the signature and the IHDR
// chunk, all that a header reader looks at, then `tail` instead of pixel data.
std::string pngHeader(uint32_t width, uint32_t height, const std::string& tail) {
    auto be32 = [](uint32_t v) { return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; };
    std::string ihdr = be32(width) + be32(height) + std::string{8, 2, 0, 0, 0};
    return std::string("\x89PNG\r\n\x1a\n", 8) + be32(13) + "IHDR" + ihdr + be32(0) + tail;
}

std::string dataUri(const std::string& bytes) {
    return "data:image/png;base64," + penumbra::test::base64(std::vector<uint8_t>(bytes.begin(), bytes.end()));
}

}  // namespace

TEST(HostileInputs, GltfImagesOfOneFileAreDecodedOnce) {
    // 24 images naming one file: one texture (it was decoded and held 24 times).
    fs::path dir = penumbra::test::freshTempDir();
    std::vector<uint8_t> rgb(2 * 2 * 3, 128);
    penumbra::writePngRgb8(dir / "t.png", 2, 2, rgb);
    penumbra::test::writeFile(dir / "model.gltf", modelWithImages(std::vector<json>(24, {{"uri", "t.png"}})));
    penumbra::Scene scene = penumbra::loadScene(dir / "model.gltf");
    EXPECT_EQ(scene.textures.size(), 1u);
}

TEST(HostileInputs, GltfImagesPastTheTexelLimitAreRefusedBeforeDecoding) {
    // Three images whose headers claim 8192 x 8192 (2^26 texels each; the limit is 2^27 in
    // all) and that hold no pixel data: refused by their sizes, naming the third, rather
    // than decoded (which would fail at the first, or with real data hold gigabytes).
    fs::path dir = penumbra::test::freshTempDir();
    std::vector<json> images;
    for (char tail : {'a', 'b', 'c'}) images.push_back({{"uri", dataUri(pngHeader(8192, 8192, std::string(1, tail)))}});
    penumbra::test::writeFile(dir / "model.gltf", modelWithImages(images));
    std::string err;
    int status = penumbra::test::runPenumbraBounded(
        "render " + quoted(dir / "model.gltf") + " -o " + quoted(dir / "out.exr") + " --quiet", 30, 1024, &err);
    EXPECT_EQ(status, 2) << err;
    EXPECT_NE(err.find("model.gltf: images[2]: the model's textures exceed 134217728 texels in all"), std::string::npos)
        << err;
}

TEST(HostileInputs, ImageSizesComeFromTheHeaderBeforeDecoding) {
    // A scene's texture files offer their size to the scene's limits (AcceptImageSize)
    // before any pixel is decoded: this file has a header and no pixel data, so only a
    // refusal by size, not a decoding error, can come out of it.
    fs::path dir = penumbra::test::freshTempDir();
    const std::string bytes = pngHeader(8192, 4096, "x");
    writeBytes(dir / "big.png", bytes);
    uint32_t width = 0, height = 0;
    auto refuse = [&](uint32_t w, uint32_t h) {
        width = w;
        height = h;
        throw penumbra::InputError("refused by size");
    };
    try {
        penumbra::readImageFile(dir / "big.png", "big.png", penumbra::ColorDecode::Srgb, penumbra::kMaxImagePixels,
                                refuse);
        ADD_FAILURE() << "accepted";
    } catch (const penumbra::InputError& e) {
        EXPECT_STREQ(e.what(), "refused by size");
    }
    EXPECT_EQ(width, 8192u);
    EXPECT_EQ(height, 4096u);
    EXPECT_EQ(penumbra::imageSize(bytes, "big.png"), std::make_pair(8192u, 4096u));
}

namespace {

// A 4 x 4 render-like image of `value` everywhere, with spp and seed 0 in its header.
penumbra::Image flatRender(float value, int spp = 4) {
    penumbra::Image image;
    image.width = image.height = 4;
    image.rgb.assign(4 * 4 * 3, value);
    image.meta.spp = spp;
    image.meta.seed = 0;
    image.meta.sampleOffset = 0;
    return image;
}

std::string fileBytes(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(HostileInputs, MergeRefusesNanAndNegativePixels) {
    for (float bad : {std::nanf(""), -0.5f, INFINITY}) {
        penumbra::Image a = flatRender(1.0f), b = flatRender(1.0f);
        b.meta.sampleOffset = 4;
        b.rgb[3 * 6 + 1] = bad;  // pixel (2, 1), green
        try {
            penumbra::mergeImages({a, b}, {"a.exr", "b.exr"});
            ADD_FAILURE() << bad << ": merged";
        } catch (const penumbra::InputError& e) {
            EXPECT_NE(std::string(e.what()).find("b.exr: pixel (2, 1) is NaN, infinite or negative"), std::string::npos)
                << e.what();
        }
    }
}

TEST(HostileInputs, MergeOfManyForgedPiecesIsNotQuadratic) {
    // Two inputs of 200k interleaved one-sample pieces each (a merge of merges could hold
    // them): compared pair by pair that took a minute (4 * 10^10 pairs); sorted, under a second.
    fs::path dir = penumbra::test::freshTempDir();
    for (int part = 0; part < 2; ++part) {
        penumbra::Image image = flatRender(1.0f, 200000);
        image.meta.pieces.emplace();
        for (int64_t k = 0; k < 200000; ++k) image.meta.pieces->push_back({0, 2 * k + part, 2 * k + part + 1});
        penumbra::writeExr(dir / ("p" + std::to_string(part) + ".exr"), image);
    }
    std::string err;
    int status = penumbra::test::runPenumbraBounded(
        "merge " + quoted(dir / "p0.exr") + " " + quoted(dir / "p1.exr") + " -o " + quoted(dir / "m.exr"), 20, 2048,
        &err);
    ASSERT_EQ(status, 0) << err;
    EXPECT_EQ(penumbra::readExr(dir / "m.exr").meta.pieces, (std::vector<penumbra::SamplePiece>{{0, 0, 400000}}));
    // One more piece that overlaps: still found.
    penumbra::Image extra = flatRender(1.0f, 1);
    extra.meta.sampleOffset = 123457;
    penumbra::writeExr(dir / "x.exr", extra);
    status = penumbra::test::runPenumbraBounded("merge " + quoted(dir / "p0.exr") + " " + quoted(dir / "p1.exr") + " " +
                                                    quoted(dir / "x.exr") + " -o " + quoted(dir / "m2.exr"),
                                                20, 2048, &err);
    EXPECT_EQ(status, 2) << err;
    EXPECT_NE(err.find("x.exr: sample indices [123457, 123458) overlap with " + (dir / "p1.exr").string()),
              std::string::npos)
        << err;
}

TEST(HostileInputs, ExrHeaderClaimingAHugeImageCostsNoMemory) {
    // A 4 x 16384 render whose header is edited to claim a 16384 x 16384 data window (3 GiB
    // as float RGB) over the same data (its offset table whole, its rows 4 pixels wide):
    // compare and merge check sizes from the headers and find the data does not fit before
    // they allocate the image.
    fs::path dir = penumbra::test::freshTempDir();
    auto writeHuge = [&](const fs::path& file, int sampleOffset) {
        penumbra::Image image = flatRender(1.0f);
        image.height = 16384;
        image.rgb.assign(size_t(4) * 16384 * 3, 1.0f);
        image.meta.sampleOffset = sampleOffset;
        penumbra::writeExr(file, image);
        std::string bytes = fileBytes(file);
        const std::string key("dataWindow\0box2i\0", 17);
        size_t at = bytes.find(key);
        ASSERT_NE(at, std::string::npos);
        at += key.size() + 4;  // the attribute's size, then xMin, yMin, xMax, yMax (little-endian int32)
        const int32_t last = 16383;
        std::memcpy(&bytes[at + 8], &last, 4);  // xMax
        writeBytes(file, bytes);
    };
    penumbra::writeExr(dir / "small.exr", flatRender(1.0f));
    writeHuge(dir / "huge.exr", 0);
    writeHuge(dir / "huge2.exr", 4);
    std::string err;
    int status = penumbra::test::runPenumbraBounded(
        "compare " + quoted(dir / "huge.exr") + " " + quoted(dir / "small.exr"), 30, 1024, &err);
    EXPECT_EQ(status, 2) << err;
    EXPECT_NE(err.find("huge.exr: size 16384x16384 differs from"), std::string::npos) << err;
    // Two of them agree in size: the missing pixel data is found by the last row's read.
    status = penumbra::test::runPenumbraBounded(
        "merge " + quoted(dir / "huge.exr") + " " + quoted(dir / "huge2.exr") + " -o " + quoted(dir / "m.exr"), 30,
        1024, &err);
    EXPECT_EQ(status, 2) << err;
    EXPECT_NE(err.find("huge.exr: cannot read OpenEXR image"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "m.exr"));
}
