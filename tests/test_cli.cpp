// The command line from the outside, as scripts use it: exit statuses, one-line errors
// naming file and JSON path, nothing written on failure, deterministic output, merge,
// compare and devices.
#include <sys/wait.h>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>

#include <gtest/gtest.h>
#include <vulkan/vulkan.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "image/image.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

json smallScene() {
    return test::floorAndSphereScene({.width = 24, .height = 16, .spp = 4, .integrator = "ao", .floorMaterial = true});
}

fs::path writeText(const std::string& name, const std::string& text) {
    fs::path path = test::outputPath(name);
    std::ofstream(path) << text;
    return path;
}

// Runs `render FILE -o OUT` on a bad input and checks the contract of SCENE_FORMAT.md.
// The error names the file at fault: the scene, or `culprit` when that is another file.
void expectBadInput(const std::string& name, const std::string& text, const std::string& mustMention,
                    const std::string& culprit = "") {
    fs::path scene = writeText(name, text);
    fs::path out = test::outputPath(name + ".exr");
    fs::remove(out);
    std::string err;
    int status = test::runPenumbra("render '" + scene.string() + "' -o '" + out.string() + "' --quiet", &err);
    EXPECT_EQ(status, 2) << name << ": " << err;
    const std::string& file = culprit.empty() ? name : culprit;
    EXPECT_NE(err.find(file), std::string::npos) << "error does not name " << file << ": " << err;
    EXPECT_NE(err.find(mustMention), std::string::npos) << "error does not mention " << mustMention << ": " << err;
    ASSERT_FALSE(err.empty());
    EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line: " << err;
    EXPECT_FALSE(fs::exists(out)) << "output written for bad input " << name;
}

}  // namespace

TEST(Cli, BadSceneInputsExitTwoWithOneLineNamingFileAndPath) {
    json doc = smallScene();
    doc["shapes"][1]["material"] = "flor";
    expectBadInput("unknown-material.json", doc.dump(), "shapes[1].material");

    doc = smallScene();
    doc["shapes"][1]["radius"] = -1;
    expectBadInput("negative-radius.json", doc.dump(), "shapes[1].radius");

    std::string text = smallScene().dump();
    text.replace(text.find("\"radius\":0.5"), 12, "\"radius\":1e999");
    expectBadInput("infinite-radius.json", text, "shapes[1].radius");

    doc = smallScene();
    doc["shapes"][0]["edge_v"] = {0, 0, 8};  // parallel to edge_u: zero area
    expectBadInput("zero-area-quad.json", doc.dump(), "shapes[0]");

    doc = smallScene();
    doc["shapes"].push_back({{"type", "mesh"}, {"positions", {0, 0, 0, 1, 0, 0, 0, 1, 0}}, {"indices", {0, 1, 3}}});
    expectBadInput("index-out-of-range.json", doc.dump(), "shapes[2].indices");

    std::string truncated = smallScene().dump(2);
    expectBadInput("truncated.json", truncated.substr(0, truncated.size() / 2), "line");

    doc = smallScene();
    doc["shapes"].push_back({{"type", "gltf"}, {"file", "no-such-model.glb"}});
    expectBadInput("missing-gltf.json", doc.dump(), "no-such-model.glb", "no-such-model.glb");

    writeText("malformed.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [ {\"primitives\": [ {");
    doc = smallScene();
    doc["shapes"].push_back({{"type", "gltf"}, {"file", "malformed.gltf"}});
    expectBadInput("bad-gltf.json", doc.dump(), "line 1", "malformed.gltf");
}

TEST(Cli, MissingFilesAndBadUsageExitTwo) {
    std::string err;
    fs::path out = test::outputPath("never.exr");
    fs::remove(out);
    EXPECT_EQ(test::runPenumbra("render /no/such/scene.json -o '" + out.string() + "'", &err), 2);
    EXPECT_NE(err.find("/no/such/scene.json"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(test::runPenumbra("render", &err), 2);
    EXPECT_EQ(test::runPenumbra("frobnicate", &err), 2);
    EXPECT_EQ(test::runPenumbra("merge /no/such/a.exr -o '" + out.string() + "'", &err), 2);
    EXPECT_NE(err.find("/no/such/a.exr"), std::string::npos) << err;
}

TEST(Cli, NoVulkanDeviceExitsOneWithClearMessage) {
    fs::path scene = writeText("novulkan.json", smallScene().dump());
    std::string err;
    int status = test::runPenumbra("render '" + scene.string() + "' -o '" +
                                       test::outputPath("novulkan.exr").string() + "'",
                                   &err);
    (void)status;  // the normal run must work; then the same with no driver at all:
    std::string cmd = "env VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json '" +
                      std::string(PENUMBRA_EXECUTABLE) + "' render '" + scene.string() + "' -o '" +
                      test::outputPath("novulkan2.exr").string() + "' 2>'" +
                      test::outputPath("novulkan.txt").string() + "'";
    int raw = std::system(cmd.c_str());
    EXPECT_EQ(WEXITSTATUS(raw), 1);
    std::ifstream in(test::outputPath("novulkan.txt"));
    std::string line;
    std::getline(in, line);
    EXPECT_NE(line.find("Vulkan"), std::string::npos) << line;
    EXPECT_FALSE(fs::exists(test::outputPath("novulkan2.exr")));
}

TEST(Cli, SameCommandGivesIdenticalPixelsAndOverridesApply) {
    fs::path scene = writeText("determinism.json", smallScene().dump());
    fs::path a = test::outputPath("det-a.exr"), b = test::outputPath("det-b.exr");
    std::string args = " --spp 8 --set integrator.sampling=uniform --quiet";
    ASSERT_EQ(test::runPenumbra("render '" + scene.string() + "' -o '" + a.string() + "'" + args), 0);
    ASSERT_EQ(test::runPenumbra("render '" + scene.string() + "' -o '" + b.string() + "'" + args), 0);
    Image ia = readExr(a), ib = readExr(b);
    ASSERT_EQ(ia.rgb.size(), ib.rgb.size());
    EXPECT_EQ(0, std::memcmp(ia.rgb.data(), ib.rgb.data(), ia.rgb.size() * sizeof(float)));
    EXPECT_EQ(ia.meta.spp, 8);
    EXPECT_NE(ia.meta.integrator->find("uniform"), std::string::npos) << *ia.meta.integrator;
    EXPECT_EQ(ia.width, 24u);
    EXPECT_EQ(ia.height, 16u);
}

TEST(Cli, DisjointPartialsMergeToTheFullRender) {
    fs::path scene = writeText("merge.json", smallScene().dump());
    fs::path p0 = test::outputPath("part0.exr"), p1 = test::outputPath("part1.exr");
    fs::path full = test::outputPath("full.exr"), merged = test::outputPath("merged.exr");
    std::string s = "render '" + scene.string() + "' --quiet ";
    ASSERT_EQ(test::runPenumbra(s + "--spp 6 -o '" + p0.string() + "'"), 0);
    ASSERT_EQ(test::runPenumbra(s + "--spp 6 --set sampler.sample_offset=6 -o '" + p1.string() + "'"), 0);
    ASSERT_EQ(test::runPenumbra(s + "--spp 12 -o '" + full.string() + "'"), 0);
    ASSERT_EQ(test::runPenumbra("merge '" + p0.string() + "' '" + p1.string() + "' -o '" + merged.string() + "'"), 0);
    Image m = readExr(merged), f = readExr(full);
    EXPECT_EQ(m.meta.spp, 12);
    // The sample indices of the partials are exactly those of the full render, so the
    // images agree up to floating-point summation order.
    ASSERT_EQ(m.rgb.size(), f.rgb.size());
    for (size_t i = 0; i < m.rgb.size(); ++i) ASSERT_NEAR(m.rgb[i], f.rgb[i], 1e-5f * (1.0f + f.rgb[i])) << i;
    // Overlapping partials are refused.
    std::string err;
    EXPECT_EQ(test::runPenumbra("merge '" + p0.string() + "' '" + p0.string() + "' -o '" + merged.string() + "'", &err), 2);
}

// light_selection "bvh" through --set: rendered, recorded in the EXR header's integrator
// JSON; a misspelling is bad input (exit 2, one line naming the file and JSON path).
TEST(Cli, LightSelectionBvhIsAcceptedRecordedAndCheckedBySet) {
    fs::path scene = writeText(
        "selection.json",
        test::floorAndSphereScene(
            {.width = 24, .height = 16, .spp = 4, .floorMaterial = true, .sphereLight = true, .pointLight = true})
            .dump());
    fs::path out = test::outputPath("selection-bvh.exr"), bad = test::outputPath("selection-bad.exr");
    std::string s = "render '" + scene.string() + "' --quiet --spp 4 ";
    std::string err;
    ASSERT_EQ(test::runPenumbra(s + "--set integrator.light_selection=bvh -o '" + out.string() + "'", &err), 0) << err;
    Image image = readExr(out);
    ASSERT_TRUE(image.meta.integrator);
    EXPECT_NE(image.meta.integrator->find("\"light_selection\":\"bvh\""), std::string::npos) << *image.meta.integrator;
    fs::remove(bad);
    EXPECT_EQ(test::runPenumbra(s + "--set integrator.light_selection=bvhh -o '" + bad.string() + "'", &err), 2);
    EXPECT_NE(err.find("selection.json: integrator.light_selection: \"bvhh\" is not one of"), std::string::npos) << err;
    EXPECT_EQ(err.find('\n'), err.size() - 1) << err;
    EXPECT_FALSE(fs::exists(bad));
}

TEST(Cli, SamplerTypeIsRecordedAndOverridable) {
    fs::path scene = writeText("sampler.json", smallScene().dump());
    fs::path sobol = test::outputPath("sampler-sobol.exr"), independent = test::outputPath("sampler-independent.exr");
    fs::path merged = test::outputPath("sampler-merged.exr");
    std::string s = "render '" + scene.string() + "' --quiet --spp 4 ";
    ASSERT_EQ(test::runPenumbra(s + "-o '" + sobol.string() + "'"), 0);
    ASSERT_EQ(test::runPenumbra(s + "--set sampler.type=independent --set sampler.sample_offset=4 -o '" +
                                independent.string() + "'"),
              0);
    Image a = readExr(sobol), b = readExr(independent);
    EXPECT_EQ(a.meta.sampler, "sobol");  // the default
    EXPECT_EQ(b.meta.sampler, "independent");
    // Partials of different samplers are refused, with one line.
    std::string err;
    EXPECT_EQ(test::runPenumbra("merge '" + sobol.string() + "' '" + independent.string() + "' -o '" +
                                merged.string() + "'", &err),
              2);
    EXPECT_NE(err.find("sampler independent differs"), std::string::npos) << err;
    EXPECT_EQ(err.find('\n'), err.size() - 1) << err;
    EXPECT_FALSE(fs::exists(merged));
    // A bad value is bad input: exit 2, one line with the JSON path, nothing written.
    fs::path bad = test::outputPath("sampler-bad.exr");
    fs::remove(bad);
    EXPECT_EQ(test::runPenumbra(s + "--set sampler.type=halton -o '" + bad.string() + "'", &err), 2);
    EXPECT_NE(err.find("sampler.json: sampler.type: \"halton\" is not one of"), std::string::npos) << err;
    EXPECT_EQ(err.find('\n'), err.size() - 1) << err;
    EXPECT_FALSE(fs::exists(bad));
}

// A device list or name without llvmpipe's SIMD width ("llvmpipe (LLVM 15.0.6, 256 bits)"
// -> "llvmpipe (LLVM 15.0.6)"): penumbra may choose another width than this process has
// (tests/test_llvmpipe_width.cpp checks that choice).
std::string withoutLlvmpipeWidth(const std::string& text) {
    static const std::regex width(R"(, \d+ bits\))");
    return std::regex_replace(text, width, ")");
}

// Device 0 as the Vulkan loader reports it to this process, queried here without
// penumbra's own code: its name, and its driver as "<driverName>, <driverInfo>" ("" without
// driver properties). Empty when there is no device.
struct FirstDevice {
    std::string name, driverName, driver;
};
FirstDevice firstDevice() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    VkInstance instance = VK_NULL_HANDLE;
    if (vkCreateInstance(&info, nullptr, &instance) != VK_SUCCESS) return {};
    uint32_t count = 1;
    VkPhysicalDevice device = VK_NULL_HANDLE;
    FirstDevice first;
    VkResult result = vkEnumeratePhysicalDevices(instance, &count, &device);
    if ((result == VK_SUCCESS || result == VK_INCOMPLETE) && count > 0) {
        VkPhysicalDeviceDriverProperties props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
        VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        props2.pNext = &props;
        vkGetPhysicalDeviceProperties2(device, &props2);
        first.name = props2.properties.deviceName;
        first.driverName = props.driverName;
        if (!first.driverName.empty()) first.driver = first.driverName + ", " + props.driverInfo;
    }
    vkDestroyInstance(instance, nullptr);
    return first;
}

TEST(Cli, CompareAndDevicesPrintForScripts) {
    fs::path scene = writeText("compare.json", smallScene().dump());
    fs::path a = test::outputPath("cmp-a.exr");
    ASSERT_EQ(test::runPenumbra("render '" + scene.string() + "' --quiet -o '" + a.string() + "'"), 0);
    std::string out;
    ASSERT_EQ(test::runPenumbra("compare '" + a.string() + "' '" + a.string() + "'", nullptr, &out), 0);
    EXPECT_NE(out.find("rmse 0\n"), std::string::npos) << out;
    EXPECT_NE(out.find("relmse 0\n"), std::string::npos) << out;
    EXPECT_NE(out.find("mean_a "), std::string::npos) << out;
    EXPECT_NE(out.find("max_abs 0\n"), std::string::npos) << out;
    ASSERT_EQ(test::runPenumbra("devices", nullptr, &out), 0);
    const FirstDevice first = firstDevice();
    ASSERT_FALSE(first.name.empty()) << "no Vulkan device";
    EXPECT_NE(withoutLlvmpipeWidth(out).find("* 0: " + withoutLlvmpipeWidth(first.name)), std::string::npos) << out;
}

TEST(Cli, DevicesPrintsTheDriverAndItsMesaVersion) {
    const FirstDevice first = firstDevice();
    ASSERT_FALSE(first.driver.empty()) << "lavapipe and GPU drivers report VK_KHR_driver_properties";
    std::string out;
    ASSERT_EQ(test::runPenumbra("devices", nullptr, &out), 0);
    // The line under device 0 names the same driver and version as the loader reports
    // (lavapipe on the machines that run the tests; "NVIDIA, 580.159.04" on an H200).
    out = withoutLlvmpipeWidth(out);
    size_t device = out.find("* 0: " + withoutLlvmpipeWidth(first.name));
    ASSERT_NE(device, std::string::npos) << out;
    size_t lineEnd = out.find('\n', device);
    ASSERT_NE(lineEnd, std::string::npos) << out;
    std::string next = out.substr(lineEnd + 1, out.find('\n', lineEnd + 1) - lineEnd - 1);
    EXPECT_EQ(next.rfind("    driver: " + first.driver, 0), 0u) << out;
    // On lavapipe that is the Mesa release, e.g. "llvmpipe, Mesa 22.3.6 (LLVM 15.0.6)".
    if (first.driverName == "llvmpipe") {
        EXPECT_TRUE(std::regex_search(next, std::regex(R"(driver: llvmpipe, Mesa \d+\.\d+\.\d+)"))) << next;
    }
}

TEST(Cli, GltfModelRendersDirectlyWithTheStudioLightsNote) {
    // The model has no lights: it is lit by a sky and a key light, said once on stderr
    // (and not with --quiet). Its own pixels are lit, not black.
    std::string modelFile = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/models/torus_knot.glb";
    fs::path out = test::outputPath("torus.exr");
    std::string err;
    ASSERT_EQ(test::runPenumbra("render '" + modelFile + "' --width 48 --height 32 --spp 4 -o '" + out.string() + "'", &err), 0)
        << err;
    EXPECT_NE(err.find("key light"), std::string::npos) << err;
    Image image = readExr(out);
    EXPECT_EQ(image.width, 48u);
    EXPECT_EQ(image.meta.spp, 4);
    // The framing camera shows the model and the background (the sky's radiance 0.4, exactly).
    // The key light lights the faces it sees above what the sky alone gives a white
    // surface (0.4 times the albedo): some model pixels are brighter than the sky.
    int model = 0, background = 0, keyLit = 0;
    for (size_t i = 0; i < image.rgb.size(); i += 3) {
        if (image.rgb[i] == 0.4f) ++background;
        else if (image.rgb[i] > 0.0f) ++model;
        keyLit += image.rgb[i] > 0.45f;
    }
    EXPECT_GT(model, 48 * 32 / 10);
    EXPECT_GT(background, 48 * 32 / 10);
    EXPECT_GT(keyLit, model / 10);
    ASSERT_EQ(test::runPenumbra("render '" + modelFile + "' --width 48 --height 32 --spp 1 --quiet -o '" + out.string() + "'", &err), 0);
    EXPECT_EQ(err, "");
}

TEST(Cli, EveryExampleSceneRendersSomething) {
    // A small render of each scene in scenes/ must see light: a scene whose emitters face
    // away from everything renders black, which no closed-form test would notice.
    for (const auto& entry : fs::directory_iterator(fs::path(PENUMBRA_SOURCE_DIR) / "scenes")) {
        if (entry.path().extension() != ".json") continue;
        fs::path out = test::outputPath("example-" + entry.path().stem().string() + ".exr");
        std::string err;
        ASSERT_EQ(test::runPenumbra("render '" + entry.path().string() + "' --width 40 --height 30 --spp 4 --quiet -o '" +
                                        out.string() + "'",
                                    &err),
                  0)
            << entry.path() << ": " << err;
        Image image = readExr(out);
        // Pixels that are lit but not looking straight at an emitter or the sky.
        int reflected = 0;
        for (size_t i = 0; i < image.rgb.size(); i += 3)
            if (image.rgb[i] + image.rgb[i + 1] + image.rgb[i + 2] > 0.0f && image.rgb[i] < 0.99f) ++reflected;
        EXPECT_GT(reflected, 40 * 30 / 10) << entry.path() << " is (almost) black";
    }
}
