// Strategy "ris" from the outside (and its specialization values): accepted in a scene file, by --set and in a batch job,
// recorded in the EXR header (with ris_candidates, which other strategies leave out); a bad
// ris_candidates, or ris without draws, is bad input (exit 2, one line naming the file and
// JSON path, no output written); the preview's strategy key 5 picks it.
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "image/image.h"
#include "preview/integrator_controls.h"
#include "preview/key_bindings.h"
#include "render/kernel_options.h"
#include "render_helpers.h"
#include "scene/integrator_json.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

fs::path writeScene(const std::string& name, const json& doc) {
    fs::path path = test::outputPath(name);
    std::ofstream(path) << doc.dump(2);
    return path;
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

bool samePixels(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// `render` of `doc` (with `set`) fails with exit 2 and one line naming the file and `path`.
void expectBadInput(const std::string& name, const json& doc, const std::string& set, const std::string& mention) {
    fs::path scene = writeScene(name, doc), out = test::outputPath(name + ".exr");
    fs::remove(out);
    std::string err;
    EXPECT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(out) + set, &err), 2) << name << ": " << err;
    EXPECT_NE(err.find(name + ": " + mention), std::string::npos) << err;
    ASSERT_FALSE(err.empty());
    EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line: " << err;
    EXPECT_FALSE(fs::exists(out)) << name;
}

}  // namespace

TEST(RisInput, SceneSetAndBatchRenderTheSameRecordedImage) {
    json doc = test::smallLitScene();
    doc["integrator"] = {{"type", "direct"}, {"strategy", "ris"}, {"ris_candidates", 5}};
    fs::path inFile = writeScene("ris-in-file.json", doc), fromFile = test::outputPath("ris-in-file.exr");
    std::string err;
    ASSERT_EQ(test::runPenumbra("render " + q(inFile) + " --quiet -o " + q(fromFile), &err), 0) << err;
    Image image = readExr(fromFile);
    ASSERT_TRUE(image.meta.integrator);
    const json header = json::parse(*image.meta.integrator);
    EXPECT_EQ(header["strategy"], "ris");
    EXPECT_EQ(header["ris_candidates"], 5);

    // The same through --set on a mis scene, and through a batch job's set.
    fs::path plain = writeScene("ris-plain.json", test::smallLitScene()), bySet = test::outputPath("ris-by-set.exr");
    const std::string set = " --set integrator.strategy=ris --set integrator.ris_candidates=5";
    ASSERT_EQ(test::runPenumbra("render " + q(plain) + " --quiet -o " + q(bySet) + set, &err), 0) << err;
    EXPECT_TRUE(samePixels(readExr(bySet), image));
    EXPECT_EQ(readExr(bySet).meta.integrator, image.meta.integrator);

    fs::path dir = test::outputPath("ris-batch");
    fs::remove_all(dir);
    fs::create_directories(dir);
    writeScene("ris-batch/scene.json", test::smallLitScene());
    json jobs = {{"jobs",
                  {{{"scene", "scene.json"},
                    {"output", "ris.exr"},
                    {"set", {"integrator.strategy=ris", "integrator.ris_candidates=5"}}}}}};
    fs::path jobFile = writeScene("ris-batch/jobs.json", jobs);
    ASSERT_EQ(test::runPenumbra("batch " + q(jobFile), &err), 0) << err;
    EXPECT_TRUE(samePixels(readExr(dir / "ris.exr"), image));

    // Another strategy's header does not list ris_candidates.
    fs::path mis = test::outputPath("ris-mis.exr");
    ASSERT_EQ(test::runPenumbra("render " + q(plain) + " --quiet -o " + q(mis), &err), 0) << err;
    EXPECT_FALSE(json::parse(*readExr(mis).meta.integrator).contains("ris_candidates"));
}

TEST(RisInput, BadCandidatesOrNoDrawsExitTwoNamingFileAndPath) {
    json doc = test::smallLitScene();
    doc["integrator"] = {{"type", "direct"}, {"strategy", "ris"}, {"ris_candidates", 0}};
    expectBadInput("ris-zero.json", doc, "", "integrator.ris_candidates");
    doc["integrator"]["ris_candidates"] = 65;
    expectBadInput("ris-too-many.json", doc, "", "integrator.ris_candidates");
    doc["integrator"]["ris_candidates"] = 2.5;
    expectBadInput("ris-fraction.json", doc, "", "integrator.ris_candidates");
    doc["integrator"]["ris_candidates"] = "8";
    expectBadInput("ris-string.json", doc, "", "integrator.ris_candidates");
    expectBadInput("ris-set.json", test::smallLitScene(),
                   " --set integrator.strategy=ris --set integrator.ris_candidates=100", "integrator.ris_candidates");
    doc["integrator"] = {{"type", "direct"}, {"strategy", "ris"}, {"light_samples", 0}};
    expectBadInput("ris-no-draws.json", doc, "", "integrator");
    doc["integrator"] = {{"type", "direct"}, {"strategy", "riss"}};
    expectBadInput("ris-misspelt.json", doc, "", "integrator.strategy");
}

TEST(RisInput, PreviewKeyFivePicksRis) {
    ASSERT_TRUE(preview::actionForKeyName("5").has_value());
    EXPECT_EQ(*preview::actionForKeyName("5"), preview::Action::StrategyRis);
    EXPECT_NE(preview::keyHelp().find("strategy ris"), std::string::npos) << preview::keyHelp();
    IntegratorSettings settings;
    EXPECT_TRUE(preview::applyIntegratorAction(settings, preview::Action::StrategyRis));
    EXPECT_EQ(settings.strategy, Strategy::Ris);
    EXPECT_EQ(integratorJson(settings)["strategy"], "ris");
    EXPECT_EQ(preview::integratorLabel(settings), "ris, spheres solid_angle");
}

// ris_candidates reaches the kernel (SPEC_RIS_CANDIDATES) under ris alone: another strategy's
// kernel keeps the default, so that the option does not split its pipeline cache; the ray
// bound of a ris sample counts each draw's BRDF candidates and its shadow ray.
TEST(RisInput, CandidatesSpecializeOnlyTheRisKernel) {
    KernelOptions a, b;
    a.integrator.strategy = b.integrator.strategy = Strategy::Mis;
    b.integrator.risCandidates = 16;
    EXPECT_TRUE(a == b);
    a.integrator.strategy = b.integrator.strategy = Strategy::Ris;
    EXPECT_FALSE(a == b);
    EXPECT_EQ(b.specialization()[SPEC_RIS_CANDIDATES], 16u);
    EXPECT_EQ(b.specialization()[SPEC_STRATEGY], gpu::STRATEGY_RIS);
    b.integrator.lightSamples = 3;
    b.integrator.bsdfSamples = 2;
    EXPECT_EQ(b.lightAndBsdfSamples(), 3u * (2u + 1u));
}
