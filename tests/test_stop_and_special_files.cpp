// Issue 49, item 7: signals during a load, and inputs that are not regular files.
// - A FIFO named as a scene, texture, environment map, glTF model or image, mesh file,
//   preview script or merge/compare input is refused at once, in one line naming it, with
//   exit status 2: opening one used to wait forever for a writer, deaf to SIGINT/SIGTERM.
//   Each run is under a timeout, so a regression fails instead of hanging.
// - The readers stop at the next chunk when a stop has been asked for (core/stop_request.h):
//   input files, image decoding, environment maps.
// - `render` exits with status 1 on SIGTERM/SIGINT at any moment, also before the render
//   loop (the default action's 143/130 before).
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/input_file.h"
#include "core/stop_request.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "image/image_file.h"
#include "render_helpers.h"
#include "scene/load.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

fs::path dir(const std::string& name) { return test::freshOutputDir("stop-special", name); }

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Waits until the child has exec'd penumbra and the dynamic loader has mapped its
// libraries (libvulkan), i.e. main is about to run: a signal before that finds the
// default action whatever main does.
bool waitForExec(pid_t pid) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < deadline) {
        std::error_code ec;
        const fs::path exe = fs::read_symlink("/proc/" + std::to_string(pid) + "/exe", ec);
        if (!ec && fs::equivalent(exe, PENUMBRA_EXECUTABLE, ec) &&
            slurp("/proc/" + std::to_string(pid) + "/maps").find("libvulkan") != std::string::npos)
            return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
}

void makeFifo(const fs::path& path) {
    fs::remove(path);
    ASSERT_EQ(::mkfifo(path.c_str(), 0644), 0) << path;
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

// Runs `args` with a 60 s limit; expects exit status 2 and one line naming `file` as a FIFO.
void expectFifoRefused(const std::string& args, const fs::path& file) {
    std::string err;
    const int status = test::runPenumbraBounded(args, 60, 4096, &err);
    EXPECT_EQ(status, 2) << args << "\n" << err;
    EXPECT_NE(err.find(file.filename().string()), std::string::npos) << err;
    EXPECT_NE(err.find("not a regular file: a FIFO"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

json sceneWith(const json& material, const json& lights = json::array()) {
    json doc =
        test::floorAndSphereScene({.width = 8, .height = 8, .spp = 1, .floorMaterial = true, .pointLight = true});
    if (!material.is_null()) doc["materials"]["floor"] = material;
    if (!lights.empty()) doc["lights"] = lights;
    return doc;
}

}  // namespace

TEST(SpecialFiles, FifoInputsAreRefusedInsteadOfWaitingForAWriter) {
    const fs::path d = dir("fifo");
    const fs::path out = d / "out.exr";
    // The scene file itself.
    makeFifo(d / "scene.json");
    expectFifoRefused("render " + q(d / "scene.json") + " --quiet -o " + q(out), d / "scene.json");
    // A texture and an environment map.
    makeFifo(d / "tex.png");
    writeText(d / "textured.json", sceneWith({{"type", "diffuse"}, {"albedo", {{"texture", "tex.png"}}}}).dump());
    expectFifoRefused("render " + q(d / "textured.json") + " --quiet -o " + q(out), d / "tex.png");
    makeFifo(d / "sky.exr");
    writeText(d / "sky.json", sceneWith(nullptr, json::array({{{"type", "environment"}, {"file", "sky.exr"}}})).dump());
    expectFifoRefused("render " + q(d / "sky.json") + " --quiet -o " + q(out), d / "sky.exr");
    // A mesh file, a glTF model given directly, and a job file.
    makeFifo(d / "mesh.ply");
    json meshScene = sceneWith(nullptr);
    meshScene["shapes"].push_back({{"type", "mesh"}, {"file", "mesh.ply"}});
    writeText(d / "mesh.json", meshScene.dump());
    expectFifoRefused("render " + q(d / "mesh.json") + " --quiet -o " + q(out), d / "mesh.ply");
    makeFifo(d / "model.gltf");
    expectFifoRefused("render " + q(d / "model.gltf") + " --quiet -o " + q(out), d / "model.gltf");
    makeFifo(d / "jobs.json");
    expectFifoRefused("batch --list " + q(d / "jobs.json"), d / "jobs.json");
    // merge and compare inputs (OpenEXR's own reader).
    makeFifo(d / "part.exr");
    expectFifoRefused("merge " + q(d / "part.exr") + " -o " + q(d / "merged.exr"), d / "part.exr");
    expectFifoRefused("compare " + q(d / "part.exr") + " " + q(d / "part.exr"), d / "part.exr");
    EXPECT_FALSE(fs::exists(out));
}

TEST(SpecialFiles, GltfImageAndScriptFifosAreRefused) {
    const fs::path d = dir("fifo-gltf");
    makeFifo(d / "image.png");
    EXPECT_THROW(readImageFile(d / "image.png", ColorDecode::Srgb), InputError);
    try {
        readInputFile(d / "image.png", "image.png", 1 << 20);
        ADD_FAILURE() << "a FIFO was read";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "image.png: cannot open file (not a regular file: a FIFO)");
    }
    // A character device is refused as well, not read up to the cap.
    try {
        readInputFile("/dev/zero", "/dev/zero", 1 << 20);
        ADD_FAILURE() << "/dev/zero was read";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "/dev/zero: cannot open file (not a regular file: a character device)");
    }
}

TEST(StopRequest, ReadersStopWhenAStopWasAskedFor) {
    const fs::path d = dir("stop");
    const fs::path scene = d / "scene.json";
    writeText(scene, sceneWith(nullptr).dump());
    Image sky;
    sky.width = 64;
    sky.height = 32;
    sky.rgb.assign(size_t(64) * 32 * 3, 0.5f);
    writeExr(d / "sky.exr", sky);
    EXPECT_NO_THROW(readInputFile(scene, "scene", 1 << 20));
    EXPECT_NO_THROW(readImageFile(d / "sky.exr", ColorDecode::Linear));
    requestStop();
    EXPECT_THROW(readInputFile(scene, "scene", 1 << 20), Stopped);
    EXPECT_THROW(loadScene(scene), Stopped);
    // A stop between reading the file and decoding it is seen by the decoder.
    EXPECT_THROW(decodeExr(slurp(d / "sky.exr"), "sky.exr"), Stopped);
    clearStopRequest();
    EXPECT_NO_THROW(loadScene(scene));
}

TEST(StopRequest, RenderExitsWithStatusOneOnASignalAtAnyMoment) {
    const fs::path d = dir("render-signal");
    json doc = test::floorAndSphereScene(
        {.width = 64, .height = 48, .spp = 1 << 20, .floorMaterial = true, .sphereLight = true, .pointLight = true});
    writeText(d / "scene.json", doc.dump());
    // Early (loading, opening the device, compiling kernels) and late (rendering): each
    // must end with status 1 and write nothing.
    for (int signal : {SIGTERM, SIGINT})
        for (int delayMs : {10, 50, 200, 800}) {
            SCOPED_TRACE(testing::Message() << "signal " << signal << " after " << delayMs << " ms");
            const fs::path out = d / "out.exr";
            pid_t pid = fork();
            ASSERT_GE(pid, 0);
            if (pid == 0) {
                const int devNull = ::open("/dev/null", O_WRONLY);
                dup2(devNull, 2);
                execl(PENUMBRA_EXECUTABLE, PENUMBRA_EXECUTABLE, "render", (d / "scene.json").c_str(), "--quiet", "-o",
                      out.c_str(), static_cast<char*>(nullptr));
                _exit(127);
            }
            EXPECT_TRUE(waitForExec(pid));
            std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
            kill(pid, signal);
            int status = 0;
            const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
            while (waitpid(pid, &status, WNOHANG) == 0) {
                if (std::chrono::steady_clock::now() > deadline) {
                    kill(pid, SIGKILL);
                    waitpid(pid, &status, 0);
                    ADD_FAILURE() << "no exit within 60 s of the signal";
                    break;
                }
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
            }
            EXPECT_TRUE(WIFEXITED(status)) << "ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
            if (WIFEXITED(status)) EXPECT_EQ(WEXITSTATUS(status), 1);
            EXPECT_FALSE(fs::exists(out));
        }
}
