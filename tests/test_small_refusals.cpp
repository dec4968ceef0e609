// Issue 49, item 9: the smaller failures, each refused or reported in words now. Cases
// that once ran long or grew (a forged JPEG size) run `penumbra` under a time and memory
// limit (runPenumbraBounded), so that a regression fails instead of stalling the run.
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/exit_status.h"
#include "gltf_builder.h"
#include "gpu_fixture.h"
#include "image/atomic_file.h"
#include "image/image.h"
#include "image/image_file.h"
#include "image/stb_image_write_static.h"
#include "preview/input_script.h"
#include "render_helpers.h"
#include "scene/load.h"
#include "scene_test_util.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

fs::path smallScene(const fs::path& dir) {
    return test::writeFile(dir / "scene.json",
                           test::floorAndSphereScene({.width = 8, .height = 8, .spp = 1, .pointLight = true}).dump());
}

// A 64 x 64 JPEG of noise (so that its data is large), as stb_image_write writes it.
std::string noiseJpeg() {
    std::vector<uint8_t> rgb(64 * 64 * 3);
    std::mt19937 rng(7);
    for (uint8_t& v : rgb) v = uint8_t(rng());
    std::string bytes;
    stbi_write_jpg_to_func([](void* context, void* data,
                              int size) { static_cast<std::string*>(context)->append(static_cast<char*>(data), size); },
                           &bytes, 64, 64, 3, rgb.data(), 90);
    return bytes;
}

std::string imageError(const fs::path& file) {
    try {
        readImageFile(file, ColorDecode::Srgb);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << file << " was read";
    return "";
}

}  // namespace

TEST(SmallRefusals, OutputNameWhoseTemporaryDoesNotFitIsRefusedBeforeRendering) {
    const fs::path dir = test::freshTempDir();
    const fs::path scene = smallScene(dir);
    // 251 bytes fit a file name (255), but not with the temporary's ".tmp-PID-N".
    const fs::path tooLong = dir / (std::string(247, 'a') + ".exr");
    std::string err;
    EXPECT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(tooLong), &err), 1) << err;
    EXPECT_NE(err.find("file name too long (251 bytes; at most 229"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    // The longest name accepted is written.
    const fs::path longest = dir / (std::string(225, 'b') + ".exr");
    EXPECT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(longest), &err), 0) << err;
    EXPECT_TRUE(fs::exists(longest));
}

TEST(SmallRefusals, DataUriErrorsDoNotEchoTheirContents) {
    const fs::path dir = test::freshTempDir();
    test::GltfBuilder b;
    b.addMeshNode(b.triangle());
    json doc = json::parse(b.gltf());
    const std::string junk(1 << 20, '!');
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + junk;
    const std::string message = test::loadError(test::writeFile(dir / "buffer.gltf", doc.dump()));
    EXPECT_LT(message.size(), 400u) << message.substr(0, 400);
    EXPECT_NE(message.find("bytes)"), std::string::npos) << message.substr(0, 400);
}

TEST(SmallRefusals, TruncatedJpegIsRefused) {
    const fs::path dir = test::freshTempDir();
    const std::string jpeg = noiseJpeg();
    test::writeFile(dir / "whole.jpg", jpeg);
    EXPECT_NO_THROW(readImageFile(dir / "whole.jpg", ColorDecode::Srgb));
    for (double kept : {0.1, 0.5, 0.95}) {
        SCOPED_TRACE(kept);
        const fs::path cut = test::writeFile(dir / "cut.jpg", jpeg.substr(0, size_t(double(jpeg.size()) * kept)));
        EXPECT_NE(imageError(cut).find("cannot decode JPEG image: data ends early"), std::string::npos);
    }
}

TEST(SmallRefusals, ForgedJpegSizeIsRefusedFromTheHeader) {
    const fs::path dir = test::freshTempDir();
    std::string jpeg = noiseJpeg();
    // SOF0 (FF C0): length (2), precision (1), height (2), width (2).
    const size_t sof = jpeg.find("\xff\xc0");
    ASSERT_NE(sof, std::string::npos);
    for (size_t at : {sof + 5, sof + 7}) {
        jpeg[at] = char(0x20);  // 8192
        jpeg[at + 1] = char(0x00);
    }
    test::writeFile(dir / "tex.jpg", jpeg);
    json doc =
        test::floorAndSphereScene({.width = 8, .height = 8, .spp = 1, .floorMaterial = true, .pointLight = true});
    doc["materials"]["floor"] = {{"type", "diffuse"}, {"albedo", {{"texture", "tex.jpg"}}}};
    const fs::path scene = test::writeFile(dir / "scene.json", doc.dump());
    // Decoding it took 18 s and 1 GiB of floats: 20 s and 768 MiB fail a regression.
    std::string err;
    EXPECT_EQ(test::runPenumbraBounded("render " + q(scene) + " --quiet -o " + q(dir / "out.exr"), 20, 768, &err), 2)
        << err;
    EXPECT_NE(err.find("tex.jpg: cannot decode JPEG image: data too short for its 8192x8192 header (at least 131072 "
                       "bytes"),
              std::string::npos)
        << err;
}

TEST(SmallRefusals, JpegHuffmanTableOfMoreThan256CodesIsRefused) {
    // stb_image 2.27 writes past its 257-entry table for such a table (tools/dev/fuzz found it,
    // ASan/UBSan: index 257 out of bounds); the marker walk refuses it before stb reads it.
    const fs::path dir = test::freshTempDir();
    std::string jpeg = noiseJpeg();
    const size_t dht = jpeg.find("\xff\xc4");
    ASSERT_NE(dht, std::string::npos);
    jpeg[dht + 5 + 14] = char(200);  // the counts of 15- and 16-bit codes: 400 codes in all
    jpeg[dht + 5 + 15] = char(200);
    const fs::path file = test::writeFile(dir / "dht.jpg", jpeg);
    EXPECT_NE(imageError(file).find("dht.jpg: cannot decode JPEG image: bad Huffman table"), std::string::npos);
    EXPECT_THROW(imageSize(jpeg, "dht.jpg"), InputError);  // the header-only reader (glTF images) too
}

TEST(SmallRefusals, PreviewScriptsAreCappedAndLongWordsElided) {
    const fs::path dir = test::freshTempDir();
    try {
        preview::loadInputScript("/dev/zero");
        ADD_FAILURE() << "/dev/zero read as a script";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
    const fs::path big = test::writeFile(dir / "big.txt", "frame 1 key q\n");
    fs::resize_file(big, preview::kMaxScriptBytes + 1);
    EXPECT_THROW(preview::loadInputScript(big), InputError);
    const fs::path word = test::writeFile(dir / "word.txt", "frame 1 " + std::string(10 << 20, 'w') + "\n");
    try {
        preview::loadInputScript(word);
        ADD_FAILURE() << "a 10 MB word was read as an event";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_LT(message.size(), 300u) << message.substr(0, 300);
        EXPECT_NE(message.find("unknown event 'wwww"), std::string::npos) << message.substr(0, 300);
        EXPECT_NE(message.find("... (10485760 bytes)'"), std::string::npos) << message.substr(0, 300);
    }
}

TEST(SmallRefusals, PenumbraDeviceMustBeAnIndexOfADevice) {
    const fs::path dir = test::freshTempDir();
    const std::string render = "render " + q(smallScene(dir)) + " --quiet -o " + q(dir / "out.exr");
    // Not an index: `devices` refuses it too. An index of no device: `devices` still lists
    // them all (that is how to find the right one), and a render refuses it.
    for (const char* value : {"4294967296", "12345678901234567890", "abc", "-1", "1.5", "99"}) {
        SCOPED_TRACE(value);
        ASSERT_EQ(setenv("PENUMBRA_DEVICE", value, 1), 0);
        std::string err;
        EXPECT_EQ(test::runPenumbra(render, &err), 2) << err;
        EXPECT_EQ(err.rfind("penumbra: PENUMBRA_DEVICE: ", 0), 0u) << err;
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
        if (std::string(value) != "99") {
            EXPECT_EQ(test::runPenumbra("devices", &err), 2) << err;
        }
    }
    unsetenv("PENUMBRA_DEVICE");
    std::string err;
    EXPECT_EQ(test::runPenumbra(render, &err), 0) << err;
}

TEST(SmallRefusals, OutOfMemorySaysWhatRanOut) {
    testing::internal::CaptureStderr();
    const int status = runReportingErrors("penumbra", []() -> int { throw std::bad_alloc(); });
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(status, 1);
    EXPECT_EQ(err.rfind("penumbra: out of memory: the host could not allocate", 0), 0u) << err;
    EXPECT_EQ(err.find("bad_alloc"), std::string::npos) << err;
}

TEST(SmallRefusals, AFailedWriteSaysWhy) {
    // A file-size limit stands in for a full disk: write() fails with EFBIG, as with ENOSPC.
    const fs::path dir = test::freshTempDir();
    const fs::path target = dir / "out.exr";
    int pipeFds[2];
    ASSERT_EQ(pipe(pipeFds), 0);
    pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        std::signal(SIGXFSZ, SIG_IGN);
        rlimit limit{1000, 1000};
        setrlimit(RLIMIT_FSIZE, &limit);
        std::string message = "no failure";
        try {
            writeOutputFile(target, std::string(100000, 'x'));
        } catch (const std::exception& e) {
            message = e.what();
        }
        (void)!write(pipeFds[1], message.data(), message.size());
        _exit(0);
    }
    close(pipeFds[1]);
    std::string message;
    char buffer[4096];
    for (ssize_t n; (n = read(pipeFds[0], buffer, sizeof buffer)) > 0;) message.append(buffer, size_t(n));
    close(pipeFds[0]);
    waitpid(pid, nullptr, 0);
    EXPECT_EQ(message, "failed to write " + target.string() + ": write error: File too large");
    EXPECT_TRUE(fs::is_empty(dir)) << "the temporary was removed";
}

TEST(SmallRefusals, PngThatFailsAfterTheExrSaysTheExrWasWritten) {
    const fs::path dir = test::freshTempDir();
    const fs::path scene = smallScene(dir);
    const fs::path fifo = dir / "no-reader.png";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
    std::string err;
    EXPECT_EQ(test::runPenumbraBounded("render " + q(scene) + " --quiet -o " + q(dir / "x.exr") + " --png " + q(fifo),
                                       60, 4096, &err),
              1)
        << err;
    EXPECT_NE(err.find("no process is reading the FIFO (" + (dir / "x.exr").string() + " was written)"),
              std::string::npos)
        << err;
    EXPECT_TRUE(fs::exists(dir / "x.exr"));
}

TEST(SmallRefusals, TasksOfZeroGetsAShortMessage) {
    const fs::path dir = test::freshTempDir();
    const fs::path jobs = test::writeFile(dir / "jobs.json", "[]");
    for (const char* args : {" --task 0 --tasks 0", " --task -1 --tasks 2"}) {
        std::string err;
        EXPECT_EQ(test::runPenumbra("batch --list " + q(jobs) + args, &err), 2) << err;
        EXPECT_LT(err.size(), 160u) << err;
        EXPECT_NE(err.find("2147483647"), std::string::npos) << err;
    }
}

TEST(SmallRefusals, GltfYfovThatRoundsTo180DegreesIsNamedAtItsOwnPath) {
    const fs::path dir = test::freshTempDir();
    test::GltfBuilder b;
    b.addMeshNode(b.triangle());
    // Below pi as a double, 180 degrees once in float.
    b.doc["cameras"] = {
        {{"type", "perspective"}, {"perspective", {{"yfov", std::numbers::pi - 1e-9}, {"znear", 0.1}}}}};
    b.addNode({{"camera", 0}, {"translation", {0, 0, 3}}});
    const std::string message = test::loadError(test::writeFile(dir / "camera.gltf", b.gltf()));
    EXPECT_NE(message.find("cameras[0].perspective.yfov: must be in (0, pi) radians"), std::string::npos) << message;
    EXPECT_EQ(message.find("fov_y"), std::string::npos) << message;
}

TEST(SmallRefusals, StaleTemporariesOfDeadWritersAreRemoved) {
    const fs::path dir = test::freshTempDir();
    const fs::path target = dir / "x.exr";
    pid_t dead = fork();
    ASSERT_GE(dead, 0);
    if (dead == 0) _exit(0);
    waitpid(dead, nullptr, 0);  // reaped: no process has this id now
    const std::string stale = "x.exr.tmp-" + std::to_string(dead) + "-3";
    const std::vector<std::string> kept = {"x.exr.tmp-1-0",                                 // init: alive
                                           "x.exr.tmp-" + std::to_string(getpid()) + "-7",  // this process's
                                           "x.exr.tmp-abc", "y.exr.tmp-" + std::to_string(dead) + "-3"};
    test::writeFile(dir / stale, "partial");
    for (const std::string& name : kept) test::writeFile(dir / name, "other");
    writeOutputFile(target, "image");
    EXPECT_FALSE(fs::exists(dir / stale));
    for (const std::string& name : kept) EXPECT_TRUE(fs::exists(dir / name)) << name;
    EXPECT_EQ(slurp(target), "image");
}

TEST(SmallRefusals, CompareRefusesImagesHoldingNan) {
    const fs::path dir = test::freshTempDir();
    Image a;
    a.width = 2;
    a.height = 1;
    a.rgb = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
    writeExr(dir / "b.exr", a);
    a.rgb[4] = std::numeric_limits<float>::quiet_NaN();
    writeExr(dir / "a.exr", a);
    std::string err, out;
    EXPECT_EQ(test::runPenumbra("compare " + q(dir / "a.exr") + " " + q(dir / "b.exr"), &err, &out), 2) << err;
    EXPECT_NE(err.find("a.exr: holds 1 NaN or infinite values (of 6)"), std::string::npos) << err;
    EXPECT_EQ(test::runPenumbra("compare " + q(dir / "b.exr") + " " + q(dir / "a.exr"), &err, &out), 2) << err;
    EXPECT_EQ(test::runPenumbra("compare " + q(dir / "b.exr") + " " + q(dir / "b.exr"), &err, &out), 0) << err;
}
