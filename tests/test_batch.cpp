// penumbra batch (docs/BATCH.md): job file validation and sweep expansion, outputs equal to
// `penumbra render` of the same job, resuming after an interruption, failing jobs that do
// not stop the others, and the reuse of pipelines and uploads between jobs. Also merge of
// N partials, which splitting one render over a cluster relies on.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "batch/job_file.h"
#include "core/errors.h"
#include "core/input_file.h"
#include "gpu/kernel_cache.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "render/renderer.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// A fresh directory build/test-output/batch/<name>.
fs::path freshDir(const std::string& name) {
    fs::path dir = test::outputPath("batch") / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

fs::path writeJson(const fs::path& path, const json& doc) {
    std::ofstream(path) << doc.dump(2);
    return path;
}

// Shell-quoted (test paths hold no quotes).
std::string q(const fs::path& p) {
    std::string quoted = p.string();
    quoted.insert(quoted.begin(), '\'');
    quoted.push_back('\'');
    return quoted;
}

bool samePixels(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// The number after `key` in the summary line ("rendered 3, skipped 1, ..."), or -1.
int summaryCount(const std::string& err, const std::string& key) {
    std::smatch m;
    if (!std::regex_search(err, m, std::regex("batch (done|interrupted): .*\\b" + key + " ([0-9]+)"))) return -1;
    return std::stoi(m[2]);
}

int countLines(const std::string& text, const std::string& needle) {
    int n = 0;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) n += line.find(needle) != std::string::npos;
    return n;
}

// loadJobFile must fail with one InputError naming the file and `jsonPath`.
void expectJobFileError(const fs::path& dir, const std::string& name, const json& doc, const std::string& jsonPath) {
    fs::path file = writeJson(dir / name, doc);
    try {
        loadJobFile(file);
        ADD_FAILURE() << name << ": accepted";
    } catch (const InputError& e) {
        std::string what = e.what();
        EXPECT_NE(what.find(file.string() + ": " + jsonPath), std::string::npos) << name << ": " << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

}  // namespace

TEST(Batch, SweepsExpandInOrderWithPlaceholdersAndPathsRelativeToTheJobFile) {
    fs::path dir = freshDir("expand");
    json doc = {
        {"set", {{"sampler.spp", 2}}},
        {"jobs",
         {{{"scene", "scenes/a.json"}, {"output", "out/single.exr"}, {"set", {"camera.fov_y=30"}}, {"png", true}},
          {{"scene", "a.json"},
           {"output", "out/frame_{i:04}.exr"},
           {"png", "png/{value}.png"},
           {"sweep", {{"path", "camera.eye"}, {"values", {{0, 1, 4}, {1.5, 1, 4}}}}}},
          {{"scene", (dir / "abs/b.json").string()},  // absolute, inside the job file's folder
           {"output", "grid/{integrator.strategy}-{sampler.spp}-{i}.exr"},
           {"set", {{"integrator.heuristic", "balance"}}},
           {"sweep",
            {{{"path", "integrator.strategy"}, {"values", {"light", "bsdf"}}},
             {{"path", "sampler.spp"}, {"values", {4, 16, 64}}}}}}}},
    };
    auto jobs = loadJobFile(writeJson(dir / "jobs.json", doc));
    ASSERT_EQ(jobs.size(), 1u + 2u + 6u);

    EXPECT_EQ(jobs[0].scene, dir / "scenes/a.json");
    EXPECT_EQ(jobs[0].output, dir / "out/single.exr");
    EXPECT_EQ(jobs[0].png, dir / "out/single.png");
    ASSERT_EQ(jobs[0].overrides.size(), 2u);  // the file's set, then the job's
    EXPECT_EQ(jobs[0].overrides[0].path, "sampler.spp");
    EXPECT_EQ(jobs[0].overrides[1].path, "camera.fov_y");
    EXPECT_EQ(jobs[0].overrides[1].value, "30");
    EXPECT_EQ(jobs[0].origin, "jobs[0]");

    EXPECT_EQ(jobs[1].output, dir / "out/frame_0000.exr");
    EXPECT_EQ(jobs[2].output, dir / "out/frame_0001.exr");
    EXPECT_EQ(jobs[2].png, dir / "png/1.5_1_4.png");
    EXPECT_EQ(jobs[2].overrides.back().path, "camera.eye");
    EXPECT_EQ(jobs[2].overrides.back().value, "[1.5,1,4]");
    EXPECT_NE(jobs[2].origin.find("jobs[1] sweep 1"), std::string::npos) << jobs[2].origin;

    // Cartesian product, the last path fastest; {i} counts within the entry.
    const char* expected[] = {"light-4-0", "light-16-1", "light-64-2", "bsdf-4-3", "bsdf-16-4", "bsdf-64-5"};
    for (int k = 0; k < 6; ++k) {
        const BatchJob& job = jobs[3 + k];
        EXPECT_EQ(job.scene, dir / "abs/b.json");
        EXPECT_EQ(job.output, dir / "grid" / (std::string(expected[k]) + ".exr"));
        ASSERT_EQ(job.overrides.size(), 4u);
        EXPECT_EQ(job.overrides[1].value, "\"balance\"");  // JSON, parsed again by applyOverride
    }

    // A bare array is a job list too.
    auto bare = loadJobFile(writeJson(dir / "bare.json", json::array({{{"scene", "s.json"}, {"output", "o.exr"}}})));
    ASSERT_EQ(bare.size(), 1u);
    EXPECT_TRUE(bare[0].overrides.empty());
}

TEST(Batch, JobFileErrorsNameFileAndJsonPath) {
    fs::path dir = freshDir("errors");
    auto job = [](json extra) {
        json j = {{"scene", "s.json"}, {"output", "o.exr"}};
        if (!extra.is_null()) j.update(extra);
        return j;
    };
    expectJobFileError(dir, "unknown-key.json", {{"jobs", {job({{"spp", 4}})}}}, "jobs[0]");
    expectJobFileError(dir, "no-output.json", {{"jobs", {{{"scene", "s.json"}}}}}, "jobs[0]: missing required field \"output\"");
    expectJobFileError(dir, "not-exr.json", {{"jobs", {job({{"output", "o.jpg"}})}}}, "jobs[0].output");
    expectJobFileError(dir, "bad-set.json", {{"jobs", {job({}), job({{"output", "p.exr"}, {"set", {"spp"}}})}}},
                       "jobs[1].set[0]");
    expectJobFileError(dir, "bad-set-path.json", {{"jobs", {job({{"set", {{"lights[x].power", 1}}}})}}},
                       "jobs[0].set");
    expectJobFileError(dir, "empty-sweep.json",
                       {{"jobs", {job({{"sweep", {{"path", "camera.eye"}, {"values", json::array()}}}})}}},
                       "jobs[0].sweep.values");
    expectJobFileError(dir, "same-output.json",
                       {{"jobs", {job({{"sweep", {{"path", "sampler.seed"}, {"values", {1, 2}}}}})}}},
                       "jobs[0].output");
    expectJobFileError(dir, "two-jobs-one-file.json", {{"jobs", {job({}), job({})}}}, "jobs[1].output");
    expectJobFileError(dir, "value-of-two.json",
                       {{"jobs",
                         {job({{"output", "{value}.exr"},
                               {"sweep",
                                {{{"path", "sampler.seed"}, {"values", {1}}},
                                 {{"path", "sampler.spp"}, {"values", {1}}}}}})}}},
                       "jobs[0].output");
    expectJobFileError(dir, "typo.json",
                       {{"jobs", {job({{"output", "{j}.exr"}, {"sweep", {{"path", "sampler.seed"}, {"values", {1}}}}})}}},
                       "jobs[0].output");
    expectJobFileError(dir, "not-a-list.json", {{"jobs", "all of them"}}, "jobs");

    // From the command line: exit 2, one line, nothing rendered.
    fs::path file = writeJson(dir / "cli.json", {{"jobs", {job({}), job({{"set", {{"sampler.spp", 1}}}, {"color", 1}})}}});
    std::string err;
    EXPECT_EQ(test::runPenumbra("batch " + q(file), &err), 2);
    EXPECT_NE(err.find(file.string() + ": jobs[1]"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(dir / "o.exr"));
    std::ofstream(dir / "syntax.json") << "{\"jobs\": [\n  {\"scene\": }\n]}";
    EXPECT_EQ(test::runPenumbra("batch " + q(dir / "syntax.json"), &err), 2);
    EXPECT_NE(err.find("line 2"), std::string::npos) << err;
    EXPECT_EQ(test::runPenumbra("batch " + q(dir / "missing.json"), &err), 2);
    EXPECT_EQ(test::runPenumbra("batch " + q(file) + " --task 1", &err), 2) << "--task without --tasks";
    EXPECT_EQ(test::runPenumbra("batch " + q(file) + " --task 3 --tasks 3", &err), 2);
}

TEST(Batch, TasksTakeEveryNthJob) {
    fs::path dir = freshDir("tasks");
    json doc = {{"jobs",
                 {{{"scene", "s.json"},
                   {"output", "f{i}.exr"},
                   {"sweep", {{"path", "sampler.seed"}, {"values", {0, 1, 2, 3, 4, 5, 6}}}}}}}};
    fs::path file = writeJson(dir / "jobs.json", doc);
    std::string out;
    ASSERT_EQ(test::runPenumbra("batch " + q(file) + " --list --task 1 --tasks 3", nullptr, &out), 0);
    std::vector<std::string> firsts;
    std::istringstream in(out);
    for (std::string line; std::getline(in, line);) firsts.push_back(line.substr(0, line.find('\t')));
    EXPECT_EQ(firsts, (std::vector<std::string>{"1", "4"})) << out;
    ASSERT_EQ(test::runPenumbra("batch " + q(file) + " --list", nullptr, &out), 0);
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 7);
}

TEST(Batch, OutputsEqualRenderOfTheSameJobAndUploadsAreReused) {
    fs::path dir = freshDir("equal");
    writeJson(dir / "scene.json", test::smallLitScene());
    json doc = {{"jobs",
                 {// Three cameras of one scene: one upload, then params only.
                  {{"scene", "scene.json"},
                   {"output", "cam{i}.exr"},
                   {"sweep", {{"path", "camera.eye"}, {"values", {{0, 1, 4}, {1, 1.5, 3}, {-1, 2, 4}}}}}},
                  // Integrator switch on the same upload: ao needs its own pipeline.
                  {{"scene", "scene.json"}, {"output", "ao.exr"}, {"set", {{"integrator", {{"type", "ao"}}}}}},
                  // Light selection changes the light tables: a new upload.
                  {{"scene", "scene.json"}, {"output", "uniform.exr"}, {"set", {"integrator.light_selection=uniform"}}},
                  // Film size: a new upload. Both new uploads take the direct pipeline from the cache.
                  {{"scene", "scene.json"}, {"output", "wide.exr"}, {"set", {{"film.width", 20}}}, {"png", true}}}}};
    fs::path file = writeJson(dir / "jobs.json", doc);
    std::string err;
    ASSERT_EQ(test::runPenumbra("batch " + q(file), &err), 0) << err;
    EXPECT_EQ(summaryCount(err, "rendered"), 6) << err;
    EXPECT_NE(err.find("scene uploads 3, reused 3; pipelines created 2, reused 2"), std::string::npos) << err;
    EXPECT_EQ(countLines(err, "scene upload reused"), 3) << err;
    EXPECT_TRUE(fs::exists(dir / "wide.png"));

    struct Case {
        const char* output;
        std::string args;
    } cases[] = {{"cam0.exr", "--set camera.eye=[0,1,4]"},
                 {"cam1.exr", "--set camera.eye=[1,1.5,3]"},
                 {"cam2.exr", "--set camera.eye=[-1,2,4]"},
                 {"ao.exr", "--set integrator={\\\"type\\\":\\\"ao\\\"}"},
                 {"uniform.exr", "--set integrator.light_selection=uniform"},
                 {"wide.exr", "--width 20"}};
    for (const Case& c : cases) {
        fs::path reference = dir / ("render-" + std::string(c.output));
        ASSERT_EQ(test::runPenumbra("render " + q(dir / "scene.json") + " --quiet -o " + q(reference) + " " + c.args,
                                    &err),
                  0)
            << err;
        Image batch = readExr(dir / c.output), render = readExr(reference);
        EXPECT_TRUE(samePixels(batch, render)) << c.output << " differs from penumbra render " << c.args;
        EXPECT_EQ(batch.meta.spp, render.meta.spp);
        EXPECT_EQ(batch.meta.integrator, render.meta.integrator);
    }
    // The images differ from each other, so the comparison above means something.
    EXPECT_FALSE(samePixels(readExr(dir / "cam0.exr"), readExr(dir / "cam1.exr")));
    EXPECT_FALSE(samePixels(readExr(dir / "cam0.exr"), readExr(dir / "uniform.exr")));
}

// A batch job may set light_selection "bvh": its own upload (the light tables differ), the
// same pixels as penumbra render with the same --set.
TEST(Batch, LightSelectionBvhJobEqualsTheRender) {
    fs::path dir = freshDir("bvh");
    writeJson(dir / "scene.json", test::smallLitScene());
    json doc = {{"jobs",
                 {{{"scene", "scene.json"}, {"output", "power.exr"}},
                  {{"scene", "scene.json"}, {"output", "bvh.exr"}, {"set", {"integrator.light_selection=bvh"}}}}}};
    fs::path file = writeJson(dir / "jobs.json", doc);
    std::string err;
    ASSERT_EQ(test::runPenumbra("batch " + q(file), &err), 0) << err;
    EXPECT_NE(err.find("scene uploads 2, reused 0"), std::string::npos) << err;
    fs::path reference = dir / "render-bvh.exr";
    ASSERT_EQ(test::runPenumbra("render " + q(dir / "scene.json") + " --quiet -o " + q(reference) +
                                    " --set integrator.light_selection=bvh",
                                &err),
              0)
        << err;
    EXPECT_TRUE(samePixels(readExr(dir / "bvh.exr"), readExr(reference)));
    EXPECT_EQ(readExr(dir / "bvh.exr").meta.integrator, readExr(reference).meta.integrator);
}

TEST(Batch, ResumeRendersOnlyMissingOrForeignOutputs) {
    fs::path dir = freshDir("resume");
    writeJson(dir / "scene.json", test::smallLitScene());
    json doc = {{"jobs",
                 {{{"scene", "scene.json"},
                   {"output", "out/f{i}.exr"},
                   {"png", true},
                   {"sweep", {{"path", "sampler.seed"}, {"values", {1, 2, 3, 4}}}}}}}};
    fs::path file = writeJson(dir / "jobs.json", doc);
    std::string err;
    ASSERT_EQ(test::runPenumbra("batch " + q(file), &err), 0) << err;  // also creates out/
    ASSERT_EQ(summaryCount(err, "rendered"), 4) << err;

    // Back-date every output so that a rewrite shows in the modification time.
    const auto old = fs::file_time_type::clock::now() - std::chrono::hours(1);
    for (int i = 0; i < 4; ++i) fs::last_write_time(dir / ("out/f" + std::to_string(i) + ".exr"), old);
    Image before = readExr(dir / "out/f1.exr");
    fs::remove(dir / "out/f1.exr");                       // interrupted before it was written
    std::ofstream(dir / "out/f2.exr") << "not an image";  // someone else's file
    fs::remove(dir / "out/f3.png");                       // the EXR is there: only the PNG is redone

    ASSERT_EQ(test::runPenumbra("batch " + q(file), &err), 0) << err;
    EXPECT_EQ(summaryCount(err, "rendered"), 2) << err;
    EXPECT_EQ(summaryCount(err, "skipped"), 2) << err;
    EXPECT_EQ(countLines(err, "f0.exr: skipped"), 1) << err;
    EXPECT_EQ(countLines(err, "f3.exr: skipped, already complete (PNG written from it)"), 1) << err;
    EXPECT_EQ(countLines(err, "f2.exr: rendered"), 1) << err;
    EXPECT_EQ(fs::last_write_time(dir / "out/f0.exr"), old);
    EXPECT_EQ(fs::last_write_time(dir / "out/f3.exr"), old);
    EXPECT_GT(fs::last_write_time(dir / "out/f1.exr"), old);
    EXPECT_TRUE(fs::exists(dir / "out/f3.png"));
    EXPECT_TRUE(samePixels(readExr(dir / "out/f1.exr"), before));
    EXPECT_EQ(readExr(dir / "out/f2.exr").meta.spp, 4);

    // A different spp makes every existing output incomplete.
    doc["jobs"][0]["set"] = {{"sampler.spp", 2}};
    writeJson(file, doc);
    ASSERT_EQ(test::runPenumbra("batch --quiet " + q(file), &err), 0) << err;
    EXPECT_EQ(summaryCount(err, "rendered"), 4) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << "--quiet leaves only the summary: " << err;

    // So does another sampler (outputs record it in penumbra:sampler).
    doc["jobs"][0]["set"]["sampler.type"] = "independent";
    writeJson(file, doc);
    ASSERT_EQ(test::runPenumbra("batch " + q(file), &err), 0) << err;
    EXPECT_EQ(summaryCount(err, "rendered"), 4) << err;
    EXPECT_EQ(countLines(err, "other sampler"), 4) << err;
    EXPECT_EQ(readExr(dir / "out/f0.exr").meta.sampler, "independent");
}

TEST(Batch, InterruptedBatchLeavesNoPartialOutputAndResumes) {
    fs::path dir = freshDir("interrupt");
    writeJson(dir / "scene.json", test::smallLitScene());
    // Job 1 would take minutes on lavapipe: it is only ever interrupted.
    json doc = {{"jobs",
                 {{{"scene", "scene.json"}, {"output", "quick.exr"}},
                  {{"scene", "scene.json"},
                   {"output", "slow.exr"},
                   {"set", {{"film.width", 128}, {"film.height", 128}, {"sampler.spp", 1000000}}}}}}};
    fs::path file = writeJson(dir / "jobs.json", doc);
    fs::path errPath = dir / "stderr.txt";

    pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        int fd = open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(fd, STDERR_FILENO);
        execl(PENUMBRA_EXECUTABLE, PENUMBRA_EXECUTABLE, "batch", file.c_str(), nullptr);
        _exit(127);
    }
    auto slurp = [&] {
        std::ifstream in(errPath);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    // Wait (bounded) until the slow job has started, then stop the batch as Slurm would.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!fs::exists(dir / "quick.exr") && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    kill(pid, SIGTERM);
    int status = 0;
    const auto stopDeadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (waitpid(pid, &status, WNOHANG) == 0) {
        if (std::chrono::steady_clock::now() > stopDeadline) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            FAIL() << "batch did not stop within 20 s of SIGTERM: " << slurp();
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    std::string err = slurp();
    ASSERT_TRUE(WIFEXITED(status)) << err;
    EXPECT_EQ(WEXITSTATUS(status), 1) << err;
    EXPECT_TRUE(fs::exists(dir / "quick.exr")) << err;
    EXPECT_FALSE(fs::exists(dir / "slow.exr")) << err;
    // The signal lands in the slow render ("interrupted, nothing written") or, on a loaded
    // machine, just before it starts; either way the slow job counts as not run.
    EXPECT_NE(err.find("batch interrupted: rendered 1, skipped 0, failed 0, not run 1,"), std::string::npos) << err;
    for (const auto& entry : fs::directory_iterator(dir))  // no temporary file left behind
        EXPECT_TRUE(entry.path().extension() != ".tmp" && entry.path().filename().string().find("slow") ==
                                                             std::string::npos)
            << entry.path();

    // Resuming: the finished job is skipped (task 0 of 2 holds only job 0).
    ASSERT_EQ(test::runPenumbra("batch " + q(file) + " --task 0 --tasks 2", &err), 0) << err;
    EXPECT_EQ(summaryCount(err, "skipped"), 1) << err;
    EXPECT_EQ(summaryCount(err, "rendered"), 0) << err;
}

TEST(Batch, FailingJobsFailAloneWithTheDocumentedStatus) {
    fs::path dir = freshDir("failures");
    writeJson(dir / "scene.json", test::smallLitScene());
    std::ofstream(dir / "not-a-dir") << "a file";
    auto good = [](const std::string& out) { return json{{"scene", "scene.json"}, {"output", out}}; };
    json runtimeOnly = {{"jobs", {good("a.exr"), good("not-a-dir/b.exr"), good("c.exr")}}};
    fs::path file = writeJson(dir / "runtime.json", runtimeOnly);
    std::string err;
    EXPECT_EQ(test::runPenumbra("batch " + q(file), &err), 1) << err;
    EXPECT_TRUE(fs::exists(dir / "a.exr"));
    EXPECT_TRUE(fs::exists(dir / "c.exr"));
    EXPECT_EQ(countLines(err, "not-a-dir/b.exr: failed: cannot write"), 1) << err;
    EXPECT_EQ(summaryCount(err, "failed"), 1) << err;

    json mixed = {{"jobs",
                   {good("d.exr"),
                    {{"scene", "missing.json"}, {"output", "e.exr"}},
                    {{"scene", "scene.json"}, {"output", "f.exr"}, {"set", {"shapes[1].radius=-1"}}},
                    good("not-a-dir/g.exr"),
                    good("h.exr")}}};
    file = writeJson(dir / "mixed.json", mixed);
    EXPECT_EQ(test::runPenumbra("batch --quiet " + q(file), &err), 2) << "bad input outranks runtime failures: " << err;
    for (const char* out : {"d.exr", "h.exr"}) EXPECT_TRUE(fs::exists(dir / out)) << out;
    for (const char* out : {"e.exr", "f.exr"}) EXPECT_FALSE(fs::exists(dir / out)) << out;
    EXPECT_EQ(countLines(err, "e.exr: failed (bad input): " + (dir / "missing.json").string()), 1) << err;
    EXPECT_EQ(countLines(err, "f.exr: failed (bad input):"), 1) << err;
    EXPECT_EQ(countLines(err, "shapes[1].radius"), 1) << err;
    EXPECT_EQ(summaryCount(err, "failed"), 3) << err;
    EXPECT_EQ(summaryCount(err, "rendered"), 2) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 4) << "three failures and the summary: " << err;
}

// A batch compiles a pipeline once for every job whose kernel options agree: the same
// integrator settings and scene features and, for a scene small enough to go inline
// (render/inline_geometry.h), the same shapes, whose coordinates are compiled into the
// kernel. Materials, emission, light power and the camera never split a pipeline; moving a
// small scene's shapes does (docs/performance-history/round-08.md: what that costs and what
// keeping the coordinates out of the kernel cost instead); a large scene's never does.
TEST(Batch, KernelCacheCompilesEachIntegratorOnce) {
    const gpu::Context& context = test::gpuContext();
    gpu::KernelCache cache(context);
    json a = test::smallLitScene(), b = test::smallLitScene(), c = test::smallLitScene();
    b["materials"]["floor"]["albedo"] = {0.8, 0.3, 0.2};
    b["shapes"][2]["emission"] = {9, 3, 1};
    b["lights"][0]["power"] = {5, 30, 5};
    c["shapes"][1]["radius"] = 0.7;
    Scene sa = test::sceneFromJson(a, "batch-cache-a"), sb = test::sceneFromJson(b, "batch-cache-b");
    Scene sc = test::sceneFromJson(c, "batch-cache-c");
    Image first, second, third;
    {
        Renderer r(context, sa, &cache);
        r.renderAll();
        first = r.readback(0);
    }
    {
        Renderer r(context, sb, &cache);
        r.renderAll();
        second = r.readback(0);
    }
    EXPECT_EQ(cache.pipelinesCreated(), 1u);
    EXPECT_EQ(cache.pipelinesReused(), 1u);
    {
        Renderer r(context, sc, &cache);
        r.renderAll();
        third = r.readback(0);
    }
    EXPECT_EQ(cache.pipelinesCreated(), 2u) << "the small scene's moved sphere is compiled into its kernel";
    EXPECT_TRUE(samePixels(first, test::renderScene(sa)));  // same as without the cache
    EXPECT_TRUE(samePixels(second, test::renderScene(sb)));
    EXPECT_TRUE(samePixels(third, test::renderScene(sc)));
    EXPECT_FALSE(samePixels(first, second));

    // Past the inline limit the shapes stay in the BVH's buffers: moving them keeps the kernel.
    json large = test::smallLitScene();
    for (int i = 0; i < int(INLINE_MAX_PRIMITIVES); ++i)
        large["shapes"].push_back({{"type", "sphere"}, {"center", {-2 + 0.08 * i, 0.05, -1.5}}, {"radius", 0.03}});
    json largeMoved = large;
    largeMoved["shapes"][1]["radius"] = 0.7;
    largeMoved["shapes"][5]["center"] = {0, 0.05, -1.2};
    Scene sl = test::sceneFromJson(large, "batch-cache-large"), slm = test::sceneFromJson(largeMoved, "batch-cache-lm");
    const KernelOptions kl = makeKernelOptions(sl, buildSceneArrays(sl));
    EXPECT_EQ(kl.inlineGeometry.slots.size(), 0u);
    EXPECT_TRUE(kl == makeKernelOptions(slm, buildSceneArrays(slm)));

    // Retarget keeps the upload and equals a fresh Renderer of the new camera.
    json moved = a;
    moved["camera"]["eye"] = {1, 2, 3};
    Scene sm = test::sceneFromJson(moved, "batch-cache-moved");
    Renderer r(context, sa, &cache);
    r.renderAll();
    r.retarget(sm);
    r.renderAll();
    EXPECT_TRUE(samePixels(r.readback(0), test::renderScene(sm)));
    json wide = a;
    wide["film"]["width"] = 20;
    EXPECT_THROW(r.retarget(test::sceneFromJson(wide, "batch-cache-wide")), std::logic_error);
}

TEST(Batch, SharesUploadComparesTheLoadedContent) {
    // Reuse is keyed on what the GPU holds, not on file names: camera, sampler and
    // integrator options change only the render parameters, anything else uploads anew.
    Scene a = test::sceneFromJson(test::smallLitScene(), "shares-upload");
    Scene b = a;
    b.path = "other.json";
    b.camera.eye = {1, 2, 3};
    b.sampler.spp = 64;
    b.integrator.type = IntegratorType::AmbientOcclusion;
    EXPECT_TRUE(sharesUpload(a, b));
    Scene c = a;
    c.integrator.lightSelection = LightSelection::Uniform;  // the light tables differ
    EXPECT_FALSE(sharesUpload(a, c));
    Scene d = a;
    d.shapes.back().center.x += 0.5f;
    EXPECT_FALSE(sharesUpload(a, d));
    Scene e = a;
    e.materials.back().kd.y *= 0.5f;
    EXPECT_FALSE(sharesUpload(a, e));
    Scene f = a;
    f.film.width += 1;
    EXPECT_FALSE(sharesUpload(a, f));
    // Environment maps by content: a map loaded twice is shared, another one is not.
    auto map = std::make_shared<EnvironmentImage>(EnvironmentImage{1, 1, {glm::vec3(1.0f)}});
    Light sky;
    sky.type = LightType::Environment;
    sky.map = map;
    Scene g = a, h = a;
    g.lights.push_back(sky);
    sky.map = std::make_shared<EnvironmentImage>(*map);
    h.lights.push_back(sky);
    EXPECT_TRUE(sharesUpload(g, h));
    sky.map = std::make_shared<EnvironmentImage>(EnvironmentImage{1, 1, {glm::vec3(2.0f)}});
    h.lights.back() = sky;
    EXPECT_FALSE(sharesUpload(g, h));
}

TEST(Batch, ASceneEditedDuringTheBatchIsUploadedAnew) {
    // Two jobs of one scene file and the same overrides, and the first job's output is the
    // scene's environment map: the second job's scene, read again, holds another map. The
    // upload was reused by path and overrides, and the second job rendered the old map.
    fs::path dir = freshDir("edited");
    Image map;
    map.width = 4;
    map.height = 4;
    map.rgb.assign(4 * 4 * 3, 1.0f);
    writeExr(dir / "sky.exr", map);
    json scene = {{"camera", {{"eye", {0, 0, 0}}, {"target", {0, 0, -1}}, {"fov_y", 30}}},
                  {"film", {{"width", 4}, {"height", 4}}},
                  {"sampler", {{"spp", 1}}},
                  {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 10}}, {"radius", 0.5}}}},
                  {"lights", {{{"type", "environment"}, {"file", "sky.exr"}, {"radiance", {2, 2, 2}}}}}};
    writeJson(dir / "scene.json", scene);
    json jobs = json::array({{{"scene", "scene.json"}, {"output", "sky.exr"}},  // replaces the map: 2 everywhere
                             {{"scene", "scene.json"}, {"output", "second.exr"}}});
    std::string err;
    ASSERT_EQ(test::runPenumbra("batch " + q(writeJson(dir / "jobs.json", jobs)) + " --quiet", &err), 0) << err;
    const Image first = readExr(dir / "sky.exr"), second = readExr(dir / "second.exr");
    for (size_t k = 0; k < first.rgb.size(); ++k) {
        EXPECT_FLOAT_EQ(first.rgb[k], 2.0f) << k;
        EXPECT_FLOAT_EQ(second.rgb[k], 4.0f) << k;  // 2 times the new map
    }
}

TEST(Batch, MergeOfNPartialsEqualsTheFullRenderAndRefusesMismatches) {
    fs::path dir = freshDir("merge");
    fs::path scene = writeJson(dir / "scene.json", test::smallLitScene());
    const int parts = 4, each = 3;
    std::string inputs;
    std::string err;
    for (int i = 0; i < parts; ++i) {
        fs::path part = dir / ("part" + std::to_string(i) + ".exr");
        ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(part) + " --spp " + std::to_string(each) +
                                        " --set sampler.sample_offset=" + std::to_string(i * each),
                                    &err),
                  0)
            << err;
        inputs += q(part) + " ";
    }
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet -o " + q(dir / "full.exr") + " --spp " +
                                    std::to_string(parts * each),
                                &err),
              0)
        << err;
    ASSERT_EQ(test::runPenumbra("merge " + inputs + "-o " + q(dir / "merged.exr"), &err), 0) << err;
    Image merged = readExr(dir / "merged.exr"), full = readExr(dir / "full.exr");
    EXPECT_EQ(merged.meta.spp, parts * each);
    EXPECT_EQ(merged.meta.sampleOffset, 0);
    ASSERT_EQ(merged.rgb.size(), full.rgb.size());
    // Same sample indices as the full render: equal up to float summation order.
    for (size_t k = 0; k < full.rgb.size(); ++k)
        ASSERT_NEAR(merged.rgb[k], full.rgb[k], 2e-5f * (1.0f + std::abs(full.rgb[k]))) << "value " << k;

    // A partial of another size.
    fs::path small = dir / "small.exr";
    ASSERT_EQ(test::runPenumbra("render " + q(scene) + " --quiet --width 8 --set sampler.sample_offset=100 -o " +
                                    q(small),
                                &err),
              0);
    EXPECT_EQ(test::runPenumbra("merge " + q(dir / "part0.exr") + " " + q(small) + " -o " + q(dir / "bad.exr"), &err), 2);
    EXPECT_NE(err.find(small.string() + ": size 8x12 differs"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    // An EXR without penumbra:spp (not a penumbra render).
    Image foreign = readExr(dir / "part1.exr");
    foreign.meta = {};
    writeExr(dir / "foreign.exr", foreign);
    EXPECT_EQ(test::runPenumbra("merge " + q(dir / "part0.exr") + " " + q(dir / "foreign.exr") + " -o " +
                                    q(dir / "bad.exr"),
                                &err),
              2);
    EXPECT_NE(err.find("foreign.exr: missing penumbra:spp"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "bad.exr"));
}

TEST(Batch, JobFilePathsStayInsideTheJobFilesFolder) {
    // As a glTF model's URIs: scenes, outputs and PNGs of a job file lie inside its folder
    // (after "..", absolute paths and symlinks), unless --allow-any-path.
    fs::path dir = freshDir("confined");
    fs::create_directories(dir / "jobs");
    fs::path jobs = dir / "jobs";
    auto job = [](json fields) {
        json j = {{"scene", "s.json"}, {"output", "o.exr"}};
        for (auto& [k, v] : fields.items()) j[k] = v;
        return j;
    };
    const char* outside = "it is outside the job file's folder";
    for (auto [name, entry, path] : std::vector<std::tuple<std::string, json, std::string>>{
             {"scene-up.json", job({{"scene", "../victim/s.json"}}), "[0].scene"},
             {"scene-abs.json", job({{"scene", "/etc/s.json"}}), "[0].scene"},
             {"output-up.json", job({{"output", "../victim/photo.exr"}}), "[0].output"},
             {"png-up.json", job({{"png", "../victim/photo.png"}}), "[0].png"},
             {"sweep-up.json",
              job({{"output", "{value}/x.exr"}, {"sweep", {{"path", "sampler.seed"}, {"values", {"a", ".."}}}}}),
              "[0].output"}}) {
        fs::path file = writeJson(jobs / name, json::array({entry}));
        try {
            loadJobFile(file);
            // A sweep value ".." becomes "__", a folder name like any other.
            if (name != "sweep-up.json") ADD_FAILURE() << name << ": accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(file.string() + ": " + path + ": refusing to use"), std::string::npos)
                << e.what();
            EXPECT_NE(std::string(e.what()).find(outside), std::string::npos) << e.what();
        }
    }
    // A symlinked folder that leads out is outside too.
    fs::create_directories(dir / "victim");
    fs::create_directory_symlink(dir / "victim", jobs / "link");
    expectJobFileError(jobs, "link.json", json::array({job({{"output", "link/photo.exr"}})}), "[0].output");
    // Opted in: all of them are read as written.
    penumbra::setAllowAnyPath(true);
    auto loaded = loadJobFile(writeJson(
        jobs / "any.json", json::array({job({{"scene", "../victim/s.json"}, {"output", "../victim/photo.exr"}})})));
    penumbra::setAllowAnyPath(false);
    ASSERT_EQ(loaded.size(), 1u);
    EXPECT_EQ(loaded[0].output, dir / "victim/photo.exr");
}

TEST(Batch, SweepValuesThatAreNoNamesBecomeUnderscores) {
    // "" gave "out/.exr" and ".." left the folder: both are written as underscores.
    fs::path dir = freshDir("no-names");
    json entry = {{"scene", "s.json"},
                  {"output", "out/{value}.exr"},
                  {"sweep", {{"path", "sampler.seed"}, {"values", {"", "..", "a.b"}}}}};
    auto jobs = loadJobFile(writeJson(dir / "jobs.json", json::array({entry})));
    ASSERT_EQ(jobs.size(), 3u);
    EXPECT_EQ(jobs[0].output, dir / "out/_.exr");
    EXPECT_EQ(jobs[1].output, dir / "out/__.exr");
    EXPECT_EQ(jobs[2].output, dir / "out/a.b.exr");
    // {i:0N} needs N >= 1 (docs/BATCH.md).
    expectJobFileError(dir, "pad0.json", json::array({{{"scene", "s.json"}, {"output", "o{i:00}.exr"}}}),
                       "[0].output: bad placeholder {i:00}");
}

TEST(Batch, JobCountsAreBoundedWithoutWrapping) {
    // 64 axes of 2 values: 2^64 jobs wrapped to 0, so the file "expanded" to nothing and
    // batch exited 0. Refused, as is a total over entries above a million.
    fs::path dir = freshDir("job-count");
    json axes = json::array();
    for (int a = 0; a < 64; ++a)
        axes.push_back({{"path", "lights[" + std::to_string(a) + "].power"}, {"values", {1, 2}}});
    expectJobFileError(dir, "wrap.json", json::array({{{"scene", "s.json"}, {"output", "o{i}.exr"}, {"sweep", axes}}}),
                       "[0].sweep: the job file expands to more than 1000000 jobs");
    // Two entries of 1000 x 600 combinations: 1.2 million in all.
    json seeds = json::array(), spps = json::array();
    for (int v = 0; v < 1000; ++v) seeds.push_back(v);
    for (int v = 1; v <= 600; ++v) spps.push_back(v);
    json sweep = {{{"path", "sampler.seed"}, {"values", seeds}}, {{"path", "sampler.spp"}, {"values", spps}}};
    json entries = json::array();
    for (const char* name : {"a{i}.exr", "b{i}.exr"})
        entries.push_back({{"scene", "s.json"}, {"output", name}, {"sweep", sweep}});
    expectJobFileError(dir, "total.json", entries, "[1].sweep: the job file expands to more than 1000000 jobs");
}
