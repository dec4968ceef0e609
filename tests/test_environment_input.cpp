// The `file` of an `environment` light as scene input: what loads (relative to the scene
// file, EXR and Radiance HDR, multiplied by `radiance`), and the one-line errors naming the
// scene file and `lights[i].file` for bad input: a missing, corrupt or non-image file, a PNG
// (the contract names EXR and HDR), negative, NaN or infinite texels, texels whose product
// with `radiance` exceeds the radiance limit, and a map beyond kMaxEnvironmentTexels; from the
// command line, exit status 2 with nothing written, and `--set lights[0].file=...` like any field.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "image/image.h"
#include "render_helpers.h"
#include "rgbe_file.h"
#include "scene/environment_file.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

void writeExrMap(const fs::path& file, uint32_t w, uint32_t h, const std::vector<glm::vec3>& texels) {
    Image image;
    image.width = w;
    image.height = h;
    for (glm::vec3 t : texels) image.rgb.insert(image.rgb.end(), {t.x, t.y, t.z});
    writeExr(file, image);
}

json sceneWithEnvironment(const json& env) {
    return {{"film", {{"width", 8}, {"height", 8}}},
            {"sampler", {{"spp", 1}}},
            {"shapes", json::array({{{"type", "sphere"}, {"center", {0, 1, 0}}, {"radius", 0.5}}})},
            {"lights", json::array({{{"type", "point"}, {"position", {0, 3, 0}}, {"power", 10}}, env})}};
}

fs::path writeScene(const fs::path& dir, const json& doc) { return test::writeFile(dir / "scene.json", doc.dump()); }

void expectError(const fs::path& dir, const std::string& file, const std::string& why) {
    fs::path scene = writeScene(dir, sceneWithEnvironment({{"type", "environment"}, {"file", file}}));
    std::string error = test::loadError(scene);
    std::string start = scene.string() + ": lights[1].file: ";
    EXPECT_EQ(error.rfind(start, 0), 0u) << "expected to start with \"" << start << "\": " << error;
    EXPECT_NE(error.find(why), std::string::npos) << "expected \"" << why << "\" in: " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << "not one line: " << error;
}

}  // namespace

TEST(EnvironmentInput, MapLoadsRelativeToTheSceneTimesRadiance) {
    fs::path dir = test::freshTempDir();
    fs::create_directories(dir / "maps");
    std::vector<glm::vec3> texels = {{1, 2, 4}, {0.5f, 0.25f, 0}, {0, 0, 0}, {8, 8, 8}, {1, 1, 1}, {2, 0, 1}};
    writeExrMap(dir / "maps" / "sky.exr", 3, 2, texels);
    test::writeRgbeHdr(dir / "maps" / "sky.hdr", 3, 2, texels);
    for (const char* file : {"maps/sky.exr", "maps/sky.hdr"}) {
        json env = {{"type", "environment"}, {"file", file}, {"radiance", {2, 1, 0.5}}};
        Scene scene = loadScene(writeScene(dir, sceneWithEnvironment(env)));
        ASSERT_EQ(scene.lights.size(), 2u);
        const Light& light = scene.lights[1];
        ASSERT_TRUE(light.map) << file;
        EXPECT_EQ(light.map->width, 3u);
        EXPECT_EQ(light.map->height, 2u);
        for (size_t i = 0; i < texels.size(); ++i)
            EXPECT_EQ(light.map->texels[i], texels[i] * glm::vec3(2, 1, 0.5f)) << file << " texel " << i;
    }
    // Without `file`: the constant sky, no map.
    Scene constant = loadScene(writeScene(dir, sceneWithEnvironment({{"type", "environment"}})));
    EXPECT_FALSE(constant.lights[1].map);
}

TEST(EnvironmentInput, BadMapsNameTheFileAndPath) {
    fs::path dir = test::freshTempDir();
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    test::writeFile(dir / "corrupt.exr", std::string("\x76\x2f\x31\x01", 4) + "not really an exr file");
    test::writeFile(dir / "corrupt.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 4 +X 4\n\x01\x02");
    test::writeFile(dir / "notes.txt", "a sky, honestly");
    writePngRgb8(dir / "sky.png", 2, 1, {10, 20, 30, 40, 50, 60});
    writeExrMap(dir / "nan.exr", 2, 1, {{1, 1, 1}, {nan, 0, 0}});
    writeExrMap(dir / "inf.exr", 2, 1, {{1, 1, 1}, {0, inf, 0}});
    writeExrMap(dir / "negative.exr", 2, 1, {{1, 1, 1}, {0.5f, -0.25f, 0}});
    writeExrMap(dir / "bright.exr", 2, 1, {{1, 1, 1}, {0, 0, 3e38f}});
    // Headers only: 8192 x 4097 is one row beyond 2^25 texels; the loader stops at the header.
    test::writeFile(dir / "huge.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4097 +X 8192\n");
    test::writeFile(dir / "wide.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 40000\n");

    expectError(dir, "missing.exr", "cannot open \"" + (dir / "missing.exr").string() + "\" (no such file)");
    expectError(dir, "corrupt.exr", "corrupt.exr: ");
    expectError(dir, "corrupt.hdr", "corrupt.hdr: cannot decode HDR image");
    expectError(dir, "notes.txt", "notes.txt: unsupported image format");
    expectError(dir, "sky.png", "sky.png: an environment map must be an OpenEXR or Radiance HDR image, not PNG");
    expectError(dir, "nan.exr", "nan.exr: image holds non-finite values");
    expectError(dir, "inf.exr", "inf.exr: image holds non-finite values");
    expectError(dir, "negative.exr", "negative.exr: texel (1, 0) = (0.5, -0.25, 0) is negative");
    expectError(dir, "bright.exr", "bright.exr: texel (1, 0) = (0, 0, 3e+38) times radiance exceeds 1e20");
    expectError(dir, "huge.hdr", "huge.hdr: image is 8192x4097, larger than the limit");
    expectError(dir, "wide.hdr", "wide.hdr: image is 40000x1, larger than the limit");
    expectError(dir, "../outside.exr", "");
    fs::path scene = writeScene(dir, sceneWithEnvironment({{"type", "environment"}, {"file", 3}}));
    EXPECT_NE(test::loadError(scene).find("lights[1].file"), std::string::npos);
    static_assert(kMaxEnvironmentTexels == 8192u * 4096u);
}

TEST(EnvironmentInput, CommandLineExitsTwoAndWritesNothing) {
    fs::path dir = test::freshOutputDir("environment-input", "cli");
    writeExrMap(dir / "negative.exr", 2, 1, {{1, 1, 1}, {-1, 0, 0}});
    fs::path scene = writeScene(dir, sceneWithEnvironment({{"type", "environment"}}));
    fs::path out = dir / "out.exr", png = dir / "out.png";
    for (const char* file : {"negative.exr", "missing.hdr"}) {
        std::string err;
        int status = test::runPenumbra("render " + test::shellQuoted(scene) + " -o " + test::shellQuoted(out) +
                                           " --png " + test::shellQuoted(png) + " --quiet --set lights[1].file=" + file,
                                       &err);
        EXPECT_EQ(status, 2) << file;
        EXPECT_NE(err.find(scene.string() + ": lights[1].file: "), std::string::npos) << err;
        EXPECT_NE(err.find(file), std::string::npos) << err;
        EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line: " << err;
        EXPECT_FALSE(fs::exists(out));
        EXPECT_FALSE(fs::exists(png));
    }
}

TEST(EnvironmentInput, FileCanBeSetFromTheCommandLine) {
    // A map of 4 everywhere set with --set replaces the constant sky of 1: an escaping camera
    // ray reads 4 instead of 1.
    fs::path dir = test::freshOutputDir("environment-input", "set");
    writeExrMap(dir / "four.exr", 2, 1, {{4, 4, 4}, {4, 4, 4}});
    json doc = sceneWithEnvironment({{"type", "environment"}});
    doc["camera"] = {{"eye", {0, 1, 5}}, {"target", {0, 6, 5}}, {"up", {0, 0, 1}}};  // straight up
    fs::path scene = writeScene(dir, doc);
    for (const std::string& set : {std::string(), std::string(" --set lights[1].file=four.exr")}) {
        fs::path out = dir / "out.exr";
        std::string err;
        ASSERT_EQ(test::runPenumbra(
                      "render " + test::shellQuoted(scene) + " -o " + test::shellQuoted(out) + " --quiet" + set, &err),
                  0)
            << err;
        Image image = readExr(out);
        EXPECT_EQ(image.rgb[0], set.empty() ? 1.0f : 4.0f) << set;
        fs::remove(out);
    }
}
