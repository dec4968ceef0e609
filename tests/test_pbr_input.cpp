// The `pbr` material in scene files (SCENE_FORMAT.md v2): defaults, the values read, and bad
// input (factors out of [0, 1], wrong types, unknown keys) as one-line errors naming the file
// and the JSON path; on the command line exit status 2 and nothing written.
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "render_helpers.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;
using test::freshTempDir;
using test::loadError;
using test::writeFile;
namespace fs = std::filesystem;

namespace {

json sceneWith(json material) {
    return {{"camera", {{"eye", {0, 1, 4}}, {"target", {0, 0.5, 0}}, {"fov_y", 40}}},
            {"film", {{"width", 16}, {"height", 12}}},
            {"sampler", {{"spp", 2}}},
            {"materials", {{"metal", material}}},
            {"shapes", {{{"type", "sphere"}, {"center", {0, 0.5, 0}}, {"radius", 0.5}, {"material", "metal"}}}},
            {"lights", {{{"type", "point"}, {"position", {0, 3, 2}}, {"intensity", 5}}}}};
}

}  // namespace

TEST(PbrInput, DefaultsAndValues) {
    const fs::path dir = freshTempDir();
    Scene s = loadScene(writeFile(dir / "defaults.json", sceneWith({{"type", "pbr"}}).dump()));
    ASSERT_EQ(s.materials.size(), 2u);
    EXPECT_EQ(s.materials[1].type, MaterialType::Pbr);
    EXPECT_EQ(s.materials[1].pbr.baseColor, glm::vec3(0.8f));
    EXPECT_EQ(s.materials[1].pbr.metallic, 0.0f);
    EXPECT_EQ(s.materials[1].pbr.roughness, 0.5f);

    json m = {{"type", "pbr"}, {"base_color", {0.9, 0.5, 0.1}}, {"metallic", 1}, {"roughness", 0}};
    s = loadScene(writeFile(dir / "values.json", sceneWith(m).dump()));
    EXPECT_EQ(s.materials[1].pbr.baseColor, glm::vec3(0.9f, 0.5f, 0.1f));
    EXPECT_EQ(s.materials[1].pbr.metallic, 1.0f);
    EXPECT_EQ(s.materials[1].pbr.roughness, 0.0f);
}

TEST(PbrInput, OutOfRangeAndMalformedFactorsNameFileAndPath) {
    const fs::path dir = freshTempDir();
    struct Case {
        json material;
        std::string path, why;
    };
    const Case cases[] = {
        {{{"type", "pbr"}, {"metallic", 1.5}}, "materials.metal.metallic", "[0, 1]"},
        {{{"type", "pbr"}, {"metallic", -0.1}}, "materials.metal.metallic", "[0, 1]"},
        {{{"type", "pbr"}, {"roughness", 2}}, "materials.metal.roughness", "[0, 1]"},
        {{{"type", "pbr"}, {"roughness", -1e-3}}, "materials.metal.roughness", "[0, 1]"},
        {{{"type", "pbr"}, {"base_color", {1.2, 0.5, 0.5}}}, "materials.metal.base_color", "[0, 1]"},
        {{{"type", "pbr"}, {"base_color", {0.5, -0.5, 0.5}}}, "materials.metal.base_color", ""},
        {{{"type", "pbr"}, {"metallic", "high"}}, "materials.metal.metallic", ""},
        {{{"type", "pbr"}, {"exponent", 20}}, "materials.metal", "exponent"},
    };
    int i = 0;
    for (const Case& c : cases) {
        const fs::path file = writeFile(dir / ("bad" + std::to_string(i++) + ".json"), sceneWith(c.material).dump());
        const std::string err = loadError(file);
        EXPECT_NE(err.find(file.filename().string()), std::string::npos) << err;
        EXPECT_NE(err.find(c.path), std::string::npos) << err;
        EXPECT_NE(err.find(c.why), std::string::npos) << err;
    }
    // A literal 1e999 is infinite: rejected by the number reader, with the path.
    std::string text = sceneWith({{"type", "pbr"}, {"roughness", 0.5}}).dump();
    text.replace(text.find("0.5,\"type\""), 3, "1e999");
    const fs::path inf = writeFile(dir / "infinite.json", text);
    EXPECT_NE(loadError(inf).find("materials.metal.roughness"), std::string::npos) << loadError(inf);
}

TEST(PbrInput, CommandLineExitsTwoAndWritesNothing) {
    const fs::path dir = test::freshOutputDir("pbr-input", "cli");
    const fs::path scene = writeFile(dir / "metal.json", sceneWith({{"type", "pbr"}, {"metallic", 3}}).dump());
    const fs::path out = dir / "metal.exr";
    std::string err;
    EXPECT_EQ(
        test::runPenumbra("render " + test::shellQuoted(scene) + " -o " + test::shellQuoted(out) + " --quiet", &err),
        2);
    EXPECT_NE(err.find("metal.json"), std::string::npos) << err;
    EXPECT_NE(err.find("materials.metal.metallic"), std::string::npos) << err;
    ASSERT_FALSE(err.empty());
    EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line: " << err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(fs::is_directory(dir));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << "something was written";
}
