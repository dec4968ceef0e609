// The output options of SCENE_FORMAT.md "Output" (v3) from the outside: -o picks EXR or PNG
// by extension (render and batch), --exposure and --tonemap shape PNGs only, a scene that
// nothing lights gets a note, both outputs may go to /dev/null, and --version.
#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu/context.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "image/tone_map.h"
#include "png_reader.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Lit by a sphere light and a point light of 400 W (radiance about 1 on the floor below it),
// bright enough that exposure +1.5 clips in places and dark enough that others do not.
json litScene() {
    json scene = test::smallLitScene();
    scene["lights"][0]["power"] = {400, 400, 400};
    return scene;
}

fs::path freshDir(const std::string& name) { return test::freshOutputDir("output-options", name); }
std::string q(const fs::path& p) { return test::shellQuoted(p); }

fs::path writeJson(const fs::path& path, const json& doc) {
    std::ofstream(path) << doc.dump(2);
    return path;
}

std::string readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

size_t fileCount(const fs::path& dir) { return size_t(std::distance(fs::directory_iterator(dir), {})); }

}  // namespace

TEST(OutputOptions, ToneCurvesFollowTheirFormulas) {
    // Narkowicz's fit, evaluated in double from the published coefficients.
    auto fit = [](double x) { return std::clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0); };
    for (double x : {1e-4, 0.01, 0.18, 0.5, 1.0, 2.0, 7.0, 100.0}) EXPECT_NEAR(acesFilmic(float(x)), fit(x), 1e-6) << x;
    // Monotone, from 0 to exactly 1, NaN and negatives black, no overflow to NaN.
    float previous = 0.0f;
    for (float x = 0.0f; x < 20.0f; x += 0.01f) {
        EXPECT_GE(acesFilmic(x), previous) << x;
        previous = acesFilmic(x);
    }
    EXPECT_EQ(acesFilmic(0.0f), 0.0f);
    EXPECT_EQ(acesFilmic(-1.0f), 0.0f);
    EXPECT_EQ(acesFilmic(NAN), 0.0f);
    EXPECT_EQ(acesFilmic(1e30f), 1.0f);
    EXPECT_EQ(acesFilmic(INFINITY), 1.0f);
    EXPECT_EQ(applyToneCurve(0.25f, ToneCurve::Clamp), 0.25f);
    EXPECT_EQ(applyToneCurve(3.0f, ToneCurve::Clamp), 1.0f);
    EXPECT_EQ(applyToneCurve(0.25f, ToneCurve::Filmic), acesFilmic(0.25f));
}

TEST(OutputOptions, OutputFormatIsToldByTheExtension) {
    const fs::path dir = freshDir("extension");
    const fs::path scene = writeJson(dir / "scene.json", litScene());
    std::string err;
    // .png alone: an sRGB PNG and no EXR, byte for byte the --png of the EXR render.
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "alone.png"), &err), 0) << err;
    EXPECT_EQ(fileCount(dir), 2u) << "only the scene and alone.png";
    ASSERT_EQ(test::runPenumbra(
                  "render " + q(scene) + " --quiet -o " + q(dir / "both.exr") + " --png " + q(dir / "both.png"), &err),
              0)
        << err;
    const test::Png alone = test::readPng(dir / "alone.png", 0);
    EXPECT_EQ(alone.width, 16);
    EXPECT_EQ(alone.channelsInFile, 3);
    EXPECT_EQ(readBytes(dir / "alone.png"), readBytes(dir / "both.png"));
    // Upper case is the same extension.
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "UPPER.PNG"), &err), 0) << err;
    EXPECT_EQ(readBytes(dir / "UPPER.PNG"), readBytes(dir / "both.png"));

    // Anything else is bad usage, one line, nothing written.
    for (const char* name : {"out.jpg", "out", "out.exr.tmp", "out.tiff"}) {
        const size_t before = fileCount(dir);
        ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / name), &err), 2) << name;
        EXPECT_NE(err.find("does not end in .exr or .png"), std::string::npos) << err;
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
        EXPECT_EQ(fileCount(dir), before) << name;
    }
}

TEST(OutputOptions, ExposureAndTonemapShapeThePngOnly) {
    const fs::path dir = freshDir("tonemap");
    const fs::path scene = writeJson(dir / "scene.json", litScene());
    std::string err;
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "plain.exr"), &err), 0) << err;
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "look.exr") + " --png " +
                                    q(dir / "look.png") + " --exposure 1.5 --tonemap filmic",
                                &err),
              0)
        << err;
    const Image plain = readExr(dir / "plain.exr"), look = readExr(dir / "look.exr");
    EXPECT_EQ(plain.rgb, look.rgb) << "the EXR must stay linear radiance";
    const test::Png png = test::readPng(dir / "look.png");
    ASSERT_EQ(png.pixels.size(), look.rgb.size());
    const float scale = std::exp2(1.5f);
    int clipped = 0;
    for (size_t i = 0; i < look.rgb.size(); ++i) {
        ASSERT_EQ(png.pixels[i], linearToSrgb8(acesFilmic(look.rgb[i] * scale))) << "value " << i;
        clipped += look.rgb[i] * scale >= 1.0f;
    }
    EXPECT_GT(clipped, 0) << "the scene must reach the shoulder for this test to mean anything";

    // An exposure alone with the default clamp.
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "dark.png") + " --exposure -2", &err),
              0)
        << err;
    const test::Png dark = test::readPng(dir / "dark.png");
    ASSERT_EQ(dark.pixels.size(), look.rgb.size());
    for (size_t i = 0; i < look.rgb.size(); ++i)
        ASSERT_EQ(dark.pixels[i], linearToSrgb8(look.rgb[i] * 0.25f)) << "value " << i;

    for (const char* bad : {"--tonemap agx", "--tonemap", "--exposure x", "--exposure 1e9"}) {
        ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "bad.png") + " " + bad, &err), 2)
            << bad;
        EXPECT_FALSE(fs::exists(dir / "bad.png"));
    }
}

TEST(OutputOptions, SceneWithNothingEmittingGetsANote) {
    const fs::path dir = freshDir("unlit");
    json unlit = test::floorAndSphereScene({.width = 8, .height = 6, .spp = 1});
    unlit.erase("lights");
    ASSERT_FALSE(unlit.contains("lights"));
    const fs::path scene = writeJson(dir / "unlit.json", unlit);
    std::string err;
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " -o " + q(dir / "a.exr"), &err), 0) << err;
    EXPECT_NE(err.find("unlit.json: no lights and no emitting shapes"), std::string::npos) << err;
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "b.exr"), &err), 0) << err;
    EXPECT_EQ(err, "");
    // A light, an emitting shape, or ambient occlusion (which needs no light): no note.
    for (const char* set : {"lights[0]={\\\"type\\\":\\\"point\\\",\\\"position\\\":[0,3,0],\\\"power\\\":10}",
                            "shapes[1].emission=[1,1,1]", "integrator.type=ao"}) {
        ASSERT_EQ(test::runPenumbra("render " + q(scene) + " -o " + q(dir / "c.exr") + " --set \"" + set + "\"", &err),
                  0)
            << set << ": " << err;
        EXPECT_EQ(err.find("no lights"), std::string::npos) << set << ": " << err;
    }
}

TEST(OutputOptions, BothOutputsMayGoToDevNull) {
    const fs::path dir = freshDir("devnull");
    const fs::path scene = writeJson(dir / "scene.json", litScene());
    std::string err;
    EXPECT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o /dev/null --png /dev/null", &err), 0) << err;
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    // A private node of /dev/null's device, so that the check cannot be passed by its name.
    const fs::path null = dir / "null";
    if (::mknod(null.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) GTEST_SKIP() << "mknod needs root";
    EXPECT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(null) + " --png " + q(null), &err), 0) << err;
    EXPECT_TRUE(fs::is_character_file(null));
    // Two regular files that are one file stay refused.
    EXPECT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "x.png") + " --png " + q(dir / "x.png"),
                                &err),
              2)
        << err;
}

TEST(OutputOptions, VersionPrintsOneLineWithTheDriver) {
    std::string err, out;
    ASSERT_EQ(test::runPenumbra("--version", &err, &out), 0) << err;
    EXPECT_EQ(err, "");
    ASSERT_FALSE(out.empty());
    EXPECT_EQ(out.find('\n'), out.size() - 1) << "not one line: " << out;
    EXPECT_EQ(out.rfind("penumbra 0.", 0), 0u) << out;
    int chosen = -1;
    const auto devices = gpu::Context::listDevices(&chosen);
    ASSERT_GE(chosen, 0);
    const gpu::DeviceInfo& d = devices[size_t(chosen)];
    EXPECT_NE(out.find(d.name), std::string::npos) << out;
    ASSERT_FALSE(d.driverName.empty()) << "lavapipe reports its driver";
    EXPECT_NE(out.find("driver " + d.driverName + " " + d.driverInfo), std::string::npos) << out;
    // Without a command and without --version: bad usage.
    EXPECT_EQ(test::runPenumbra("", &err), 2);
}

TEST(OutputOptions, BatchOutputsFollowTheSameRule) {
    const fs::path dir = freshDir("batch");
    writeJson(dir / "scene.json", litScene());
    std::string err;
    // A .png output is a PNG alone, equal to render's; a rerun skips it.
    const fs::path jobs = writeJson(dir / "jobs.json", json::array({{{"scene", "scene.json"}, {"output", "a.png"}}}));
    ASSERT_EQ(test::runPenumbra("batch " + q(jobs), &err), 0) << err;
    EXPECT_FALSE(fs::exists(dir / "a.exr"));
    ASSERT_EQ(test::runPenumbra("render " + q(dir / "scene.json") + " --quiet -o " + q(dir / "r.png"), &err), 0);
    EXPECT_EQ(readBytes(dir / "a.png"), readBytes(dir / "r.png"));
    ASSERT_EQ(test::runPenumbra("batch " + q(jobs), &err), 0) << err;
    EXPECT_NE(err.find("skipped, already complete"), std::string::npos) << err;
    // A PNG of another film size is replaced.
    const fs::path resized =
        writeJson(dir / "resized.json",
                  json::array({{{"scene", "scene.json"}, {"output", "a.png"}, {"set", {{"film.width", 8}}}}}));
    ASSERT_EQ(test::runPenumbra("batch " + q(resized), &err), 0) << err;
    EXPECT_NE(err.find("other film size"), std::string::npos) << err;
    EXPECT_EQ(test::readPng(dir / "a.png").width, 8);

    for (const json& job : {json{{"scene", "scene.json"}, {"output", "a.jpg"}},
                            json{{"scene", "scene.json"}, {"output", "b.png"}, {"png", true}}}) {
        const fs::path bad = writeJson(dir / "bad.json", json::array({job}));
        ASSERT_EQ(test::runPenumbra("batch " + q(bad), &err), 2) << job.dump();
        EXPECT_NE(err.find("bad.json: [0]."), std::string::npos) << err;
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    }
    EXPECT_FALSE(fs::exists(dir / "b.png"));
}
