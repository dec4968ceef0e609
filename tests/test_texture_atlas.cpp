// The texture atlas: the shelf layout keeps every texture and its gutter apart and within
// the image, refuses what does not fit (and the loaders say so, naming the field); the
// gutters hold each texture's repeat neighbours; and a texture far into the atlas renders
// as it does at the atlas' corner, within the sub-texel rounding its position allows.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <glm/gtc/packing.hpp>

#include "core/errors.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "render/texture_atlas.h"
#include "render_helpers.h"
#include "scene/material_textures.h"
#include "scene/texture_atlas_layout.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Whether the padded rectangles (texture + gutter) of layout `l` overlap or leave the atlas.
std::string layoutProblem(const std::vector<glm::uvec2>& sizes, const AtlasLayout& l) {
    const uint32_t g = kAtlasGutter;
    for (size_t i = 0; i < sizes.size(); ++i) {
        glm::uvec2 lo = l.origins[i] - glm::uvec2(g), hi = l.origins[i] + sizes[i] + glm::uvec2(g);
        if (l.origins[i].x < g || l.origins[i].y < g || hi.x > l.width || hi.y > l.height)
            return "texture " + std::to_string(i) + " leaves the atlas";
        for (size_t j = 0; j < i; ++j) {
            glm::uvec2 lo2 = l.origins[j] - glm::uvec2(g), hi2 = l.origins[j] + sizes[j] + glm::uvec2(g);
            if (lo.x < hi2.x && lo2.x < hi.x && lo.y < hi2.y && lo2.y < hi.y)
                return "textures " + std::to_string(j) + " and " + std::to_string(i) + " overlap";
        }
    }
    return "";
}

}  // namespace

TEST(TextureAtlas, LayoutKeepsTexturesAndGuttersApart) {
    // A few textures: one row, as wide as they are with their gutters.
    std::vector<glm::uvec2> few = {{4, 3}, {16, 16}, {1, 1}, {7, 2}};
    auto l = layoutTextureAtlas(few);
    ASSERT_TRUE(l);
    EXPECT_EQ(l->width, 6u + 18 + 3 + 9);
    EXPECT_EQ(l->height, 18u);
    EXPECT_EQ(layoutProblem(few, *l), "");
    // Many of mixed sizes: several shelves in a kAtlasMaxSize-wide atlas.
    std::vector<glm::uvec2> many;
    for (uint32_t i = 0; i < 300; ++i) many.emplace_back(17 + (i * 37) % 900, 5 + (i * 53) % 700);
    l = layoutTextureAtlas(many);
    ASSERT_TRUE(l);
    EXPECT_EQ(l->width, kAtlasMaxSize);
    EXPECT_LE(l->height, kAtlasMaxSize);
    EXPECT_EQ(layoutProblem(many, *l), "");
    // The README's examples of the texel limit: 128 of 1024 x 1024, 512 of 512 x 512.
    l = layoutTextureAtlas(std::vector<glm::uvec2>(128, glm::uvec2(1024)));
    ASSERT_TRUE(l);
    EXPECT_EQ(l->height, 9u * 1026);
    l = layoutTextureAtlas(std::vector<glm::uvec2>(512, glm::uvec2(512)));
    ASSERT_TRUE(l);
    EXPECT_EQ(l->height, 17u * 514);
    // Nothing: an empty atlas.
    l = layoutTextureAtlas({});
    ASSERT_TRUE(l);
    EXPECT_EQ(l->width * l->height, 0u);
}

TEST(TextureAtlas, LayoutRefusesWhatDoesNotFit) {
    size_t misfit = 99;
    // The largest texture fills the atlas with its gutter; one texel more does not fit.
    auto l = layoutTextureAtlas({{kAtlasMaxTextureSide, kAtlasMaxTextureSide}});
    ASSERT_TRUE(l);
    EXPECT_EQ(l->width, kAtlasMaxSize);
    EXPECT_EQ(l->height, kAtlasMaxSize);
    EXPECT_FALSE(layoutTextureAtlas({{4, 4}, {kAtlasMaxTextureSide + 1, 1}}, &misfit));
    EXPECT_EQ(misfit, 1u);
    // Four of 8190 x 8190 fill it exactly; two of 8192 x 8192 do not fit with their gutters.
    const uint32_t quarter = kAtlasMaxSize / 2 - 2;
    EXPECT_TRUE(layoutTextureAtlas(std::vector<glm::uvec2>(4, glm::uvec2(quarter))));
    EXPECT_FALSE(layoutTextureAtlas(std::vector<glm::uvec2>(5, glm::uvec2(quarter)), &misfit));
    EXPECT_EQ(misfit, 4u);
    EXPECT_FALSE(layoutTextureAtlas(std::vector<glm::uvec2>(2, glm::uvec2(kAtlasMaxSize / 2))));
}

TEST(TextureAtlas, TableRefusesTexturesThatDoNotFit) {
    std::vector<Texture> textures;
    TextureTable table(textures);
    std::string why;
    auto fail = [&](const std::string& w) {
        why = w;
        throw InputError(w);
    };
    auto texture = [](uint32_t w, uint32_t h) {
        return [w, h] {
            Texture t;
            t.file = "t.png";
            t.width = w;
            t.height = h;
            return t;
        };
    };
    table.add("a", true, texture(kAtlasMaxSize / 2, kAtlasMaxSize / 2), fail);
    EXPECT_NO_THROW(table.checkAtlas(fail));
    table.add("b", true, texture(kAtlasMaxSize / 2, kAtlasMaxSize / 2), fail);
    EXPECT_THROW(table.checkAtlas(fail), InputError);
    EXPECT_NE(why.find("textures do not fit one 16384 x 16384 texture atlas"), std::string::npos) << why;
    std::vector<Texture> one;
    TextureTable wide(one);
    wide.add("w", true, texture(kAtlasMaxTextureSide + 1, 1), fail);
    EXPECT_THROW(wide.checkAtlas(fail), InputError);
    EXPECT_NE(why.find("\"t.png\" is 16383 x 1 texels; at most 16382 on a side"), std::string::npos) << why;
}

TEST(TextureAtlas, SceneWithATooWideTextureNamesTheField) {
    fs::path dir = test::freshTempDir();
    writePngRgb8(dir / "wide.png", kAtlasMaxTextureSide + 1, 1,
                 std::vector<uint8_t>(size_t(kAtlasMaxTextureSide + 1) * 3, 128));
    json doc = {{"materials", {{"m", {{"type", "diffuse"}, {"albedo", {{"texture", "wide.png"}}}}}}},
                {"shapes", json::array()},
                {"film", {{"width", 8}, {"height", 8}}}};
    fs::path file = test::writeFile(dir / "scene.json", doc.dump());
    std::string error = test::loadError(file);
    EXPECT_EQ(error.rfind(file.string() + ": materials.m.albedo.texture: ", 0), 0u) << error;
    EXPECT_NE(error.find("is 16383 x 1 texels; at most 16382 on a side fit"), std::string::npos) << error;
}

TEST(TextureAtlas, GuttersHoldTheRepeatNeighbours) {
    // Texel values that name their texture and position: t * 1000 + y * 10 + x (exact in
    // half precision below 2048).
    std::vector<Texture> textures;
    for (glm::uvec2 size : {glm::uvec2(3, 2), glm::uvec2(1, 4), glm::uvec2(5, 5)}) {
        Texture t;
        t.width = size.x;
        t.height = size.y;
        float id = float(textures.size());
        for (uint32_t y = 0; y < size.y; ++y)
            for (uint32_t x = 0; x < size.x; ++x)
                for (int c = 0; c < 4; ++c) t.texels.push_back(glm::packHalf1x16(id * 100 + float(y * 10 + x)));
        textures.push_back(t);
    }
    TextureAtlas atlas = buildTextureAtlas(textures);
    ASSERT_EQ(atlas.origins.size(), 3u);
    ASSERT_EQ(atlas.texels.size(), size_t(atlas.width) * atlas.height * 4);
    for (size_t i = 0; i < textures.size(); ++i) {
        const Texture& t = textures[i];
        const int64_t ox = atlas.origins[i] & 0xffffu, oy = atlas.origins[i] >> 16, w = t.width, h = t.height;
        for (int64_t y = -1; y <= h; ++y)
            for (int64_t x = -1; x <= w; ++x) {
                int64_t sx = (x + w) % w, sy = (y + h) % h;  // what repeat wrapping reads there
                size_t at = size_t(((oy + y) * atlas.width + ox + x) * 4);
                for (int c = 0; c < 4; ++c)
                    ASSERT_EQ(atlas.texels[at + c], t.texels[size_t((sy * w + sx) * 4 + c)])
                        << "texture " << i << " at (" << x << ", " << y << ")";
            }
    }
    // No textures: a 1 x 1 placeholder.
    TextureAtlas none = buildTextureAtlas({});
    EXPECT_EQ(none.width * none.height, 1u);
    EXPECT_EQ(none.texels.size(), 4u);
}

TEST(TextureAtlas, TextureFarIntoTheAtlasRendersAsAtItsCorner) {
    auto dir = test::freshOutputDir("texture-atlas", "far");
    // The checkerboard of test_textures.cpp (values multiples of 1/8, steps of at most 0.5
    // between neighbours), 4 x 3 texels.
    Image checker;
    checker.width = 4;
    checker.height = 3;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x)
            checker.rgb.insert(checker.rgb.end(),
                               {(x + y) % 2 ? 0.75f : 0.25f, 0.125f + 0.25f * float(x), 0.875f - 0.25f * float(y)});
    writeExr(dir / "checker.exr", checker);
    // A filler as tall as the checkerboard and listed first, so that the layout puts the
    // checkerboard after it on the first shelf, at atlas column 8003.
    const uint32_t fillerWidth = 8000;
    writePngRgb8(dir / "filler.png", fillerWidth, 3, std::vector<uint8_t>(size_t(fillerWidth) * 3 * 3, 200));
    json quad = {
        {"type", "quad"}, {"origin", {-1, 0, -1}}, {"edge_u", {2, 0, 0}}, {"edge_v", {0, 0, 2}}, {"material", "m"}};
    json scene = {{"camera", test::topDownCamera(0, 0, 0.95)},
                  {"film", {{"width", 32}, {"height", 32}}},
                  {"sampler", {{"spp", 16}, {"seed", 5}, {"type", "independent"}}},
                  {"materials", {{"m", {{"type", "diffuse"}, {"albedo", {{"texture", "checker.exr"}}}}}}},
                  {"shapes", json::array({quad})},
                  {"lights", json::array({{{"type", "environment"}, {"radiance", 1}}})}};
    Scene alone = test::sceneFromJson(scene, "texture-atlas/far/alone");
    json withFiller = scene;
    // The filler's material first: its texture is loaded (and laid out) first. No shape
    // uses it, so the two scenes trace the same rays.
    withFiller["materials"] = {{"filler", {{"type", "diffuse"}, {"albedo", {{"texture", "filler.png"}}}}},
                               {"m", {{"type", "diffuse"}, {"albedo", {{"texture", "checker.exr"}}}}}};
    Scene far = test::sceneFromJson(withFiller, "texture-atlas/far/with-filler");
    ASSERT_EQ(far.textures.size(), 2u);
    ASSERT_EQ(far.textures[0].width, fillerWidth);
    EXPECT_EQ(buildTextureAtlas(far.textures).origins[1] & 0xffffu, fillerWidth + 3);

    Image a = test::renderScene(alone), b = test::renderScene(far);
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    // The same rays and samples (same seed and geometry): only the lookups differ. At atlas column x in [4096, 8192) a float coordinate keeps 2^-11 of a
    // texel (2^-15 near column 4), so each bilinear weight may move by 2^-11 in each axis:
    // at most 2 x 2^-11 x 0.5 (the largest step between neighbouring texels) = 4.9e-4 per
    // lookup and per pixel mean. A misplaced lookup (the filler, a neighbour texel, a missing
    // gutter at the seam the camera sees) moves values by 0.06 or more.
    double worst = 0;
    for (size_t k = 0; k < a.rgb.size(); ++k) worst = std::max(worst, double(std::fabs(a.rgb[k] - b.rgb[k])));
    EXPECT_LE(worst, 2 * std::ldexp(1.0, -11) * 0.5 + 1e-6);
    // And the placement does change the lookups' rounding (the comparison is not vacuous:
    // the texture really sits elsewhere), yet far less than a texel step.
    EXPECT_GT(worst, 0.0);
}
