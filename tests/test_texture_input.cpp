// Texture fields and mesh `uvs` in scene files: what loads (texture objects, scales,
// deduplication by file and decoding) and the one-line errors naming the scene file and
// JSON path for bad input: missing, corrupt or unsupported texture files, files outside
// the scene's folder, out-of-range scales, unknown keys and `uvs` of the wrong length; and
// from the command line, exit status 2 with nothing written.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "image/image.h"
#include "render_helpers.h"
#include "scene/load.h"
#include "scene/material_textures.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// A 2 x 2 RGB PNG of sRGB codes 0, 64, 128, 255 (grey), top row first.
void writeTexturePng(const fs::path& file) {
    std::vector<uint8_t> rgb;
    for (uint8_t code : {0, 64, 128, 255}) rgb.resize(rgb.size() + 3, code);
    writePngRgb8(file, 2, 2, rgb);
}

json sceneWith(json materials, json shapes = nullptr) {
    if (shapes.is_null())
        shapes = json::array({{{"type", "quad"},
                               {"origin", {0, 0, 0}},
                               {"edge_u", {1, 0, 0}},
                               {"edge_v", {0, 0, 1}},
                               {"material", "m"}}});
    return {{"materials", materials},
            {"shapes", shapes},
            {"film", {{"width", 8}, {"height", 8}}},
            {"sampler", {{"spp", 1}}}};
}

fs::path writeScene(const fs::path& dir, const json& doc) { return test::writeFile(dir / "scene.json", doc.dump()); }

// The error of loading `doc` from `dir`, which must name the scene file, the JSON path and
// `why` (in that order, on one line).
void expectError(const fs::path& dir, const json& doc, const std::string& path, const std::string& why) {
    fs::path file = writeScene(dir, doc);
    std::string error = test::loadError(file);
    std::string start = file.string() + ": " + path + ": ";
    EXPECT_EQ(error.rfind(start, 0), 0u) << "expected to start with \"" << start << "\": " << error;
    EXPECT_NE(error.find(why), std::string::npos) << "expected \"" << why << "\" in: " << error;
}

}  // namespace

TEST(TextureInput, TexturedFieldsLoadAndShareTheirFiles) {
    fs::path dir = test::freshTempDir();
    writeTexturePng(dir / "t.png");
    fs::create_directories(dir / "sub");
    writeTexturePng(dir / "sub" / "u.png");
    json materials = {
        {"a", {{"type", "diffuse"}, {"albedo", {{"texture", "t.png"}, {"scale", {0.5, 0.25, 1}}}}}},
        {"b", {{"type", "phong"}, {"kd", {{"texture", "t.png"}}}, {"ks", {{"texture", "sub/../t.png"}, {"scale", 0}}}}},
        {"c", {{"type", "diffuse"}, {"albedo", {{"texture", "sub/u.png"}, {"scale", 0.5}}}}},
    };
    Scene scene = loadScene(writeScene(dir, sceneWith(materials, json::array())));
    // t.png is one texture (the same file by any path, the same decoding); u.png another.
    ASSERT_EQ(scene.textures.size(), 2u);
    const Texture& t = scene.textures[0];
    EXPECT_EQ(t.width, 2u);
    EXPECT_EQ(t.height, 2u);
    EXPECT_TRUE(t.srgb);
    ASSERT_EQ(scene.materials.size(), 4u);  // the default first
    const Material& a = scene.materials[1];
    ASSERT_EQ(a.textures.size(), 1u);
    EXPECT_EQ(a.textures[0].slot, TextureSlot::Kd);
    EXPECT_EQ(a.textures[0].texture, 0u);
    EXPECT_EQ(a.textures[0].scale, glm::vec3(0.5f, 0.25f, 1.0f));
    const Material& b = scene.materials[2];
    ASSERT_EQ(b.textures.size(), 2u);
    EXPECT_EQ(b.textures[1].slot, TextureSlot::Ks);
    EXPECT_EQ(b.textures[1].texture, 0u);
    EXPECT_EQ(scene.materials[3].textures[0].texture, 1u);
    EXPECT_EQ(scene.materials[3].textures[0].scale, glm::vec3(0.5f));
}

TEST(TextureInput, TextureLimitsAreEnforced) {
    std::vector<Texture> textures;
    TextureTable table(textures);
    std::string why;
    auto fail = [&](const std::string& w) {
        why = w;
        throw InputError(w);
    };
    auto texture = [](uint32_t w, uint32_t h) {
        return [w, h](const AcceptImageSize&) {
            Texture t;
            t.width = w;
            t.height = h;
            return t;
        };
    };
    // The same key and decoding is loaded once; another decoding is another texture.
    EXPECT_EQ(table.add("a.png", true, texture(4, 4), fail), 0u);
    EXPECT_EQ(table.add("a.png", true, texture(4, 4), fail), 0u);
    EXPECT_EQ(table.add("a.png", false, texture(4, 4), fail), 1u);
    // Texels in all: 2^27 - 32 more fit, then one more texel does not.
    EXPECT_EQ(table.add("big.png", true, texture(1u << 13, (1u << 14) - 1), fail), 2u);
    uint64_t used = 32 + uint64_t(1u << 13) * ((1u << 14) - 1);
    uint64_t left = kMaxTextureTexels - used;
    EXPECT_EQ(table.add("rest.png", true, texture(uint32_t(left), 1), fail), 3u);
    EXPECT_THROW(table.add("one-more.png", true, texture(1, 1), fail), InputError);
    EXPECT_NE(why.find("exceed 134217728 texels"), std::string::npos) << why;
    // A load is refused by the size its header gives, before it decodes anything.
    bool decoded = false;
    auto fromHeader = [&](const AcceptImageSize& accept) {
        accept(1, 1);
        decoded = true;
        return Texture{};
    };
    EXPECT_THROW(table.add("header.png", true, fromHeader, fail), InputError);
    EXPECT_FALSE(decoded);
    // Count: kMaxTextures distinct textures at most.
    std::vector<Texture> many;
    TextureTable counted(many);
    for (size_t i = 0; i < kMaxTextures; ++i) counted.add(std::to_string(i), true, texture(0, 0), fail);
    EXPECT_THROW(counted.add("last", true, texture(0, 0), fail), InputError);
    EXPECT_NE(why.find("more than 4096 distinct textures"), std::string::npos) << why;
}

TEST(TextureInput, BadTexturesNameTheFileAndPath) {
    fs::path dir = test::freshTempDir();
    writeTexturePng(dir / "good.png");
    test::writeFile(dir / "corrupt.png", std::string("\x89PNG\r\n\x1a\n", 8) + "not really a png at all");
    test::writeFile(dir / "picture.gif", std::string("GIF89a\x01\x00\x01\x00", 10));
    auto albedo = [](json texture) { return json{{"m", {{"type", "diffuse"}, {"albedo", texture}}}}; };

    expectError(dir, sceneWith(albedo({{"texture", "missing.png"}})), "materials.m.albedo.texture",
                "cannot open \"" + (dir / "missing.png").string() + "\" (no such file)");
    expectError(dir, sceneWith(albedo({{"texture", "corrupt.png"}})), "materials.m.albedo.texture",
                "corrupt.png: cannot decode PNG image");
    expectError(dir, sceneWith(albedo({{"texture", "picture.gif"}})), "materials.m.albedo.texture",
                "picture.gif: unsupported image format");
    expectError(dir, sceneWith(albedo({{"texture", "../outside.png"}})), "materials.m.albedo.texture", "");
    expectError(dir, sceneWith(albedo({{"texture", "good.png"}, {"scale", 1.5}})), "materials.m.albedo.scale",
                "components must be in [0, 1]");
    expectError(dir, sceneWith(albedo({{"texture", "good.png"}, {"scale", {0.5, -0.1, 0.5}}})),
                "materials.m.albedo.scale", "must not be negative");
    expectError(dir, sceneWith(albedo({{"texture", "good.png"}, {"filter", "nearest"}})), "materials.m.albedo",
                "unknown key \"filter\"");
    expectError(dir, sceneWith(albedo({{"scale", 0.5}})), "materials.m.albedo", "texture");
    expectError(dir, sceneWith(albedo({{"texture", 3}})), "materials.m.albedo.texture", "");
    json phong = {{"m", {{"type", "phong"}, {"kd", {{"texture", "good.png"}, {"scale", 0.7}}}, {"ks", 0.5}}}};
    expectError(dir, sceneWith(phong), "materials.m", "kd + ks exceeds 1");
}

TEST(TextureInput, TextureOutsideTheSceneFolderIsRefused) {
    fs::path dir = test::freshTempDir();
    writeTexturePng(dir / "outside.png");
    fs::create_directories(dir / "scene");
    json doc = sceneWith({{"m", {{"type", "diffuse"}, {"albedo", {{"texture", "../outside.png"}}}}}});
    expectError(dir / "scene", doc, "materials.m.albedo.texture", "outside the scene's folder");
}

TEST(TextureInput, MeshUvsAreValidatedLikeNormals) {
    fs::path dir = test::freshTempDir();
    json mesh = {{"type", "mesh"}, {"positions", {0, 0, 0, 1, 0, 0, 0, 0, 1}}, {"indices", {0, 1, 2}}};
    json good = mesh;
    good["uvs"] = {0, 0, 2.5, 0, -1, 1};
    Scene scene = loadScene(writeScene(dir, sceneWith(json::object(), json::array({good}))));
    ASSERT_EQ(scene.shapes[0].uvs.size(), 3u);
    EXPECT_EQ(scene.shapes[0].uvs[1], glm::vec2(2.5f, 0.0f));
    EXPECT_EQ(scene.shapes[0].uvs[2], glm::vec2(-1.0f, 1.0f));

    json shortUvs = mesh;
    shortUvs["uvs"] = {0, 0, 1, 0, 1};
    expectError(dir, sceneWith(json::object(), json::array({shortUvs})), "shapes[0].uvs",
                "has 5 numbers, expected 2 per vertex (6)");
    json text = mesh;
    text["uvs"] = {0, 0, 1, "a", 1, 1};
    expectError(dir, sceneWith(json::object(), json::array({text})), "shapes[0].uvs[3]", "");
    std::string infinite = sceneWith(json::object(), json::array({good})).dump();
    infinite.replace(infinite.find("2.5"), 3, "1e999");
    fs::path file = test::writeFile(dir / "scene.json", infinite);
    std::string error = test::loadError(file);
    EXPECT_NE(error.find("shapes[0].uvs[2]"), std::string::npos) << error;
}

TEST(TextureInput, CommandLineExitsTwoAndWritesNothing) {
    fs::path dir = test::freshOutputDir("texture-input", "cli");
    test::writeFile(dir / "corrupt.jpg", "\xff\xd8\xff\xe0 truncated");
    json doc = sceneWith({{"m", {{"type", "diffuse"}, {"albedo", {{"texture", "corrupt.jpg"}}}}}});
    fs::path scene = test::writeFile(dir / "scene.json", doc.dump());
    fs::path out = dir / "out.exr", png = dir / "out.png";
    std::string err;
    int status = test::runPenumbra("render " + test::shellQuoted(scene) + " -o " + test::shellQuoted(out) + " --png " +
                                       test::shellQuoted(png) + " --quiet",
                                   &err);
    EXPECT_EQ(status, 2);
    EXPECT_NE(err.find(scene.string() + ": materials.m.albedo.texture: "), std::string::npos) << err;
    EXPECT_NE(err.find("corrupt.jpg: cannot decode JPEG image"), std::string::npos) << err;
    EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line: " << err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(png));
}
