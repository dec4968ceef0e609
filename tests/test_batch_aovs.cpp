// penumbra batch with AOV layers (SCENE_FORMAT.md "AOVs (v3)", docs/BATCH.md): a job asks
// for them in its scene or with `set film.aovs`, its EXR holds them as `penumbra render`
// writes them, and resuming takes a render with other layers for incomplete.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "image/image.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::string q(const fs::path& p) { return test::shellQuoted(p); }

std::vector<std::string> aovNames(const Image& image) {
    std::vector<std::string> names;
    for (const AovLayer& layer : image.aovs) names.push_back(layer.name);
    return names;
}

}  // namespace

TEST(BatchAovs, JobsWriteTheLayersTheirSceneOrSetAsksFor) {
    const fs::path dir = test::freshOutputDir("batch-aovs", "jobs");
    json scene = test::floorAndSphereScene({.width = 10, .height = 7, .spp = 2, .pointLight = true});
    std::ofstream(dir / "plain.json") << scene.dump();
    scene["film"]["aovs"] = {"normal", "material_id"};
    std::ofstream(dir / "with-aovs.json") << scene.dump();
    const json jobs = {
        {"jobs",
         {{{"scene", "plain.json"}, {"output", "set.exr"}, {"set", {{"film.aovs", {"depth", "shape_id"}}}}},
          {{"scene", "with-aovs.json"}, {"output", "scene.exr"}},
          {{"scene", "plain.json"}, {"output", "none.exr"}}}}};
    std::ofstream(dir / "jobs.json") << jobs.dump();
    std::string err;
    ASSERT_EQ(test::runPenumbra("batch " + q(dir / "jobs.json"), &err), 0) << err;

    // The same layers, value for value, as one `penumbra render` of the job.
    ASSERT_EQ(
        test::runPenumbra(
            "render " + q(dir / "plain.json") + " --quiet --aov depth,shape_id -o " + q(dir / "set-render.exr"), &err),
        0)
        << err;
    const Image set = readExr(dir / "set.exr"), reference = readExr(dir / "set-render.exr");
    EXPECT_EQ(aovNames(set), (std::vector<std::string>{"depth", "shape_id"}));
    ASSERT_EQ(set.aovs.size(), reference.aovs.size());
    for (size_t l = 0; l < set.aovs.size(); ++l) {
        EXPECT_EQ(set.aovs[l].floats, reference.aovs[l].floats) << set.aovs[l].name;
        EXPECT_EQ(set.aovs[l].ids, reference.aovs[l].ids) << set.aovs[l].name;
    }
    EXPECT_EQ(aovNames(readExr(dir / "scene.exr")), (std::vector<std::string>{"normal", "material_id"}));
    EXPECT_TRUE(readExr(dir / "none.exr").aovs.empty());

    // Resuming: complete outputs are skipped; one whose job now asks for other layers is not.
    ASSERT_EQ(test::runPenumbra("batch " + q(dir / "jobs.json"), &err), 0) << err;
    EXPECT_EQ(err.find("replaced output"), std::string::npos) << err;
    json changed = jobs;
    changed["jobs"][2]["set"] = {{"film.aovs", {"albedo"}}};
    std::ofstream(dir / "jobs.json") << changed.dump();
    ASSERT_EQ(test::runPenumbra("batch " + q(dir / "jobs.json"), &err), 0) << err;
    EXPECT_NE(err.find("replaced output: other AOVs"), std::string::npos) << err;
    EXPECT_EQ(aovNames(readExr(dir / "none.exr")), (std::vector<std::string>{"albedo"}));
}
