// Outputs from the outside (image/output_check.h, image/atomic_file.h): no run overwrites
// its own scene or writes one file twice, however the paths are spelled (render, merge,
// batch, preview); symlinked outputs keep the link; devices and FIFOs are written through,
// not replaced; every output is checked before rendering.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "image/image.h"
#include "image/output_check.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

json tinyScene() {
    return {
        {"camera", {{"eye", {0, 1, 4}}, {"target", {0, 0.5, 0}}}},
        {"film", {{"width", 16}, {"height", 8}}},
        {"sampler", {{"spp", 2}}},
        {"integrator", {{"type", "ao"}}},
        {"shapes", {{{"type", "sphere"}, {"center", {0, 0.5, 0}}, {"radius", 0.5}}}},
    };
}

fs::path freshDir(const std::string& name) { return test::freshOutputDir("outputs", name); }

std::string q(const fs::path& p) { return test::shellQuoted(p); }

std::string readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

fs::path writeScene(const fs::path& dir) {
    fs::path scene = dir / "scene.json";
    std::ofstream(scene) << tinyScene().dump();
    return scene;
}

// `render` with `args` must exit `status` with one line containing `needle`.
void expectRefused(const std::string& args, int status, const std::string& needle) {
    std::string err;
    EXPECT_EQ(test::runPenumbra(args, &err), status) << args << ": " << err;
    EXPECT_NE(err.find(needle), std::string::npos) << args << ": " << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << "not one line: " << err;
}

bool isExr(const std::string& bytes) { return bytes.size() > 4 && bytes.compare(0, 4, "\x76\x2f\x31\x01") == 0; }

}  // namespace

TEST(OutputFiles, IdentityComparesResolvedFilesNotSpellings) {
    fs::path dir = freshDir("identity");
    fs::create_directories(dir / "real");
    fs::create_symlink("real", dir / "link");
    std::ofstream(dir / "real" / "exists.json") << "{}";
    fs::create_hard_link(dir / "real" / "exists.json", dir / "hard.json");
    const fs::path cwdRelative = fs::relative(dir / "real" / "new.exr", fs::current_path());
    // A file still to be created, spelled five ways.
    for (const fs::path& p :
         {dir / "real" / "." / "new.exr", dir / "link" / "new.exr", dir / "real" / ".." / "real" / "new.exr",
          cwdRelative, fs::path(dir.string() + "//real/new.exr")})
        EXPECT_EQ(fileIdentity(p), fileIdentity(dir / "real" / "new.exr")) << p;
    // An existing file, through a symlinked folder and a hard link.
    EXPECT_EQ(fileIdentity(dir / "link" / "exists.json"), fileIdentity(dir / "real" / "exists.json"));
    EXPECT_EQ(fileIdentity(dir / "hard.json"), fileIdentity(dir / "real" / "exists.json"));
    EXPECT_NE(fileIdentity(dir / "real" / "other.exr"), fileIdentity(dir / "real" / "new.exr"));
}

TEST(OutputFiles, RenderRefusesAnOutputThatIsTheSceneOrAnotherOutput) {
    fs::path dir = freshDir("render-same");
    fs::path scene = writeScene(dir);
    const std::string before = readBytes(scene);
    fs::create_symlink("scene.json", dir / "scene-link.exr");
    fs::create_hard_link(scene, dir / "scene-hard.exr");
    const std::string r = "render " + q(scene) + " --quiet ";
    for (const fs::path& out : {scene, dir / "." / "scene.json", dir / "scene-link.exr", dir / "scene-hard.exr"}) {
        // -o takes .exr and .png names only (SCENE_FORMAT.md "Output"): the scene's own name is
        // refused for its extension before the files are compared.
        const bool exr = out.extension() == ".exr";
        expectRefused(r + "-o " + q(out), 2, exr ? "is the same file as the scene" : "does not end in .exr or .png");
        expectRefused(r + "-o " + q(dir / "fine.exr") + " --png " + q(out), 2, "is the same file as the scene");
    }
    EXPECT_EQ(readBytes(scene), before) << "the scene was overwritten";
    EXPECT_TRUE(fs::is_symlink(dir / "scene-link.exr"));

    // -o X --png X: both would land in one file; spelled two ways too.
    expectRefused(r + "-o " + q(dir / "x.exr") + " --png " + q(dir / "x.exr"), 2, "is the same file as -o");
    expectRefused(r + "-o " + q(dir / "x.exr") + " --png " + q(dir / "." / "x.exr"), 2,
                  "every output must be a file of its own");
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
    EXPECT_FALSE(fs::exists(dir / "fine.exr"));
}

TEST(OutputFiles, EveryOutputIsCheckedBeforeRendering) {
    fs::path dir = freshDir("before");
    fs::path scene = writeScene(dir);
    fs::create_directories(dir / "a-dir.png");
    // The EXR would be fine, the PNG cannot be written: nothing is rendered or written.
    expectRefused("render " + q(scene) + " --quiet -o " + q(dir / "y.exr") + " --png " + q(dir / "a-dir.png"), 1,
                  "cannot write " + (dir / "a-dir.png").string() + ": it is a directory");
    EXPECT_FALSE(fs::exists(dir / "y.exr"));
    expectRefused("render " + q(scene) + " --quiet -o " + q(dir / "no-dir" / "y.exr"), 1, "does not exist");
    EXPECT_TRUE(fs::is_directory(dir / "a-dir.png"));
}

TEST(OutputFiles, SymlinkedOutputKeepsTheLinkAndReplacesItsTargetAtomically) {
    fs::path dir = freshDir("symlink");
    fs::path scene = writeScene(dir);
    fs::create_directories(dir / "store");
    std::ofstream(dir / "store" / "real.exr") << "old";
    fs::permissions(dir / "store" / "real.exr", fs::perms::owner_read | fs::perms::owner_write);
    fs::create_symlink("store/real.exr", dir / "link.exr");
    fs::create_symlink("store/new.exr", dir / "dangling.exr");
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "link.exr")), 0);
    EXPECT_TRUE(fs::is_symlink(dir / "link.exr")) << "the link was replaced";
    EXPECT_EQ(fs::read_symlink(dir / "link.exr"), "store/real.exr");
    EXPECT_EQ(readExr(dir / "store" / "real.exr").meta.spp, 2);
    EXPECT_EQ(fs::status(dir / "store" / "real.exr").permissions() & fs::perms::all,
              fs::perms::owner_read | fs::perms::owner_write)
        << "a replaced file keeps its permissions";
    // A dangling link creates the file it names.
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "dangling.exr")), 0);
    EXPECT_TRUE(fs::is_symlink(dir / "dangling.exr"));
    EXPECT_EQ(readExr(dir / "store" / "new.exr").meta.spp, 2);
    // No temporary is left anywhere.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir / "store"), {}), 2);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 4);
}

TEST(OutputFiles, CharacterDevicesAreWrittenThroughNotReplaced) {
    fs::path dir = freshDir("device");
    fs::path scene = writeScene(dir);
    // A private node of /dev/null's device (1, 3), so that a failure cannot harm the real one.
    fs::path null = dir / "null";
    if (::mknod(null.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) GTEST_SKIP() << "mknod needs root";
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(null) + " --png " + q(dir / "n.png")), 0);
    EXPECT_TRUE(fs::is_character_file(null)) << "the device was replaced by a regular file";
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 3);  // scene, null, n.png
    // A device that may not be written fails before rendering (exit 1).
    fs::permissions(null, fs::perms::owner_read);
    if (::access(null.c_str(), W_OK) != 0)  // root ignores permission bits
        expectRefused("render " + q(scene) + " --quiet -o " + q(null), 1, "cannot write");
}

TEST(OutputFiles, FifosAreWrittenThroughAndNeverWaitedOn) {
    fs::path dir = freshDir("fifo");
    fs::path scene = writeScene(dir);
    fs::path fifo = dir / "pipe.exr";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
    // Without a reader the write fails at once (exit 1), rather than hang.
    expectRefused("render " + q(scene) + " --quiet -o " + q(fifo), 1, "no process is reading the FIFO");
    EXPECT_TRUE(fs::is_fifo(fifo));

    std::string received;
    std::thread reader([&] {
        int fd = ::open(fifo.c_str(), O_RDONLY);  // blocks until the writer opens it
        char buffer[4096];
        for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) received.append(buffer, size_t(n));
        ::close(fd);
    });
    // The reader must be waiting in open() before penumbra opens the FIFO without blocking.
    std::string err;
    int status = -1;
    for (int attempt = 0; attempt < 50; ++attempt) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        status = test::runPenumbra("render " + q(scene) + " --quiet -o " + q(fifo), &err);
        if (status == 0) break;
    }
    if (status != 0) {  // unblock the reader
        int fd = ::open(fifo.c_str(), O_WRONLY);
        ::close(fd);
    }
    reader.join();
    ASSERT_EQ(status, 0) << err;
    EXPECT_TRUE(fs::is_fifo(fifo)) << "the FIFO was replaced";
    EXPECT_TRUE(isExr(received)) << received.size() << " bytes";
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 2);
}

TEST(OutputFiles, MergeRefusesToOverwriteAnInput) {
    fs::path dir = freshDir("merge");
    fs::path scene = writeScene(dir);
    const std::string r = "render " + q(scene) + " --quiet ";
    ASSERT_EQ(test::runPenumbra(r + "-o " + q(dir / "a.exr")), 0);
    ASSERT_EQ(test::runPenumbra(r + "--set sampler.sample_offset=2 -o " + q(dir / "b.exr")), 0);
    const std::string before = readBytes(dir / "a.exr");
    std::string err;
    EXPECT_EQ(
        test::runPenumbra("merge " + q(dir / "a.exr") + " " + q(dir / "b.exr") + " -o " + q(dir / "." / "a.exr"), &err),
        2);
    EXPECT_NE(err.find("is the same file as input"), std::string::npos) << err;
    EXPECT_EQ(readBytes(dir / "a.exr"), before);
}

TEST(OutputFiles, PreviewScreenshotMayNotOverwriteTheScene) {
    fs::path dir = freshDir("preview");
    fs::path scene = writeScene(dir);
    const std::string before = readBytes(scene);
    // Checked before any window is opened, so this needs no display.
    std::string err;
    EXPECT_EQ(test::runPenumbra("preview " + q(scene) + " --frames 1 --screenshot " + q(scene), &err), 2) << err;
    EXPECT_NE(err.find("--screenshot"), std::string::npos) << err;
    EXPECT_EQ(readBytes(scene), before);
}

TEST(OutputFiles, BatchCatchesOneFileSpelledTwoWays) {
    fs::path dir = freshDir("batch");
    writeScene(dir);
    fs::create_directories(dir / "real");
    fs::create_symlink("real", dir / "link");
    auto job = [](const std::string& output) { return json{{"scene", "scene.json"}, {"output", output}}; };
    struct Case {
        json jobs;
        std::string path;  // the JSON path the message must name
    };
    const std::vector<Case> cases = {
        {{job("a.exr"), job((dir / "a.exr").string())}, "jobs[1].output"},  // relative vs absolute
        {{job("./b.exr"), job("b.exr")}, "jobs[1].output"},
        {{job("real/c.exr"), job("link/c.exr")}, "jobs[1].output"},  // a symlinked folder
        {{{{"scene", "scene.json"}, {"output", "d.exr"}, {"png", "d.png"}},
          {{"scene", "scene.json"}, {"output", "e.exr"}, {"png", "./d.png"}}},
         "jobs[1].png"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        const json& doc = cases[i].jobs;
        fs::path file = dir / ("jobs" + std::to_string(i) + ".json");
        std::ofstream(file) << json{{"jobs", doc}}.dump();
        for (const std::string extra : {"", " --list"}) {
            std::string err, out;
            EXPECT_EQ(test::runPenumbra("batch " + q(file) + extra, &err, &out), 2) << i << ": " << err;
            EXPECT_NE(err.find(file.string() + ": " + cases[i].path), std::string::npos) << i << ": " << err;
            // (The job file's own check catches spellings that normalize alike; image/
            // output_check.h catches the rest, e.g. a symlinked folder.)
            EXPECT_TRUE(err.find("is the same file as") != std::string::npos ||
                        err.find("is written by two jobs") != std::string::npos)
                << err;
            EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
            EXPECT_EQ(out, "") << "nothing listed for a bad job file";
        }
    }
    {
        // The job file named relative to the working directory, its first output relative
        // to it, the second absolute.
        const fs::path cwd = fs::current_path();
        fs::current_path(dir);
        std::string err;
        const int status = test::runPenumbra("batch jobs0.json", &err);
        fs::current_path(cwd);
        EXPECT_EQ(status, 2) << err;
        EXPECT_NE(err.find("jobs0.json: jobs[1].output"), std::string::npos) << err;
    }
    for (const char* name : {"a.exr", "b.exr", "real/c.exr", "d.exr", "e.exr", "d.png"})
        EXPECT_FALSE(fs::exists(dir / name)) << name << " was written";

    // An output that is a scene (through a symlink named like an output).
    fs::create_symlink("scene.json", dir / "scene-link.exr");
    const std::string before = readBytes(dir / "scene.json");
    fs::path file = dir / "clobber.json";
    std::ofstream(file) << json{{"jobs", {job("f.exr"), job("scene-link.exr")}}}.dump();
    std::string err;
    EXPECT_EQ(test::runPenumbra("batch " + q(file), &err), 2) << err;
    EXPECT_NE(
        err.find("jobs[1].output \"" + (dir / "scene-link.exr").string() + "\" is the same file as jobs[0].scene"),
        std::string::npos)
        << err;
    EXPECT_EQ(readBytes(dir / "scene.json"), before);
    EXPECT_FALSE(fs::exists(dir / "f.exr")) << "nothing runs when the job file is bad";
}
