// Prompt stop (render/pass_bands.h): a render is split into submissions of bounded time,
// so SIGINT/SIGTERM end `render` and `batch` within 2 s even with 65536 light and BRDF
// samples per pixel sample, writing nothing; and the split never changes a pixel.
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numeric>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "render/pass_bands.h"
#include "render/renderer.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// A floor, a sphere, a sphere light and a point light. The width is not a multiple of the
// 8-pixel tile, so runs of columns end at the film's edge too.
json litScene(uint32_t width, uint32_t height) {
    return test::floorAndSphereScene(
        {.width = width, .height = height, .spp = 3, .floorMaterial = true, .sphereLight = true, .pointLight = true});
}

bool samePixels(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

fs::path freshDir(const std::string& name) {
    fs::path dir = test::outputPath("stop") / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// Runs penumbra with `args` on a pseudo-terminal (so that it prints progress), waits until
// the progress shows the render running, sends `signal`, and returns the seconds from the
// signal to the exit; `status` gets the wait status, `output` what it printed.
double secondsToStop(const std::vector<std::string>& args, int signal, int& status, std::string& output) {
    std::vector<char*> argv{const_cast<char*>(PENUMBRA_EXECUTABLE)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    int master = -1;
    pid_t pid = forkpty(&master, nullptr, nullptr, nullptr);
    if (pid < 0) return -1.0;
    if (pid == 0) {
        execv(PENUMBRA_EXECUTABLE, argv.data());
        _exit(127);
    }
    // Reads what is there within `timeout` seconds; false at end of output.
    auto pump = [&](double timeout) {
        fd_set set;
        FD_ZERO(&set);
        FD_SET(master, &set);
        timeval tv{0, int(timeout * 1e6)};
        if (select(master + 1, &set, nullptr, nullptr, &tv) <= 0) return true;
        char buffer[4096];
        ssize_t n = read(master, buffer, sizeof buffer);
        if (n <= 0) return false;
        output.append(buffer, size_t(n));
        return true;
    };
    // "N/M spp" is printed after each submission of the render loop.
    const auto startDeadline = Clock::now() + std::chrono::seconds(120);
    while (output.find(" spp") == std::string::npos && Clock::now() < startDeadline)
        if (!pump(0.05)) break;
    if (output.find(" spp") == std::string::npos) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        close(master);
        return -1.0;
    }
    const auto signalled = Clock::now();
    kill(pid, signal);
    const auto stopDeadline = signalled + std::chrono::seconds(60);
    while (waitpid(pid, &status, WNOHANG) == 0) {
        if (Clock::now() > stopDeadline) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            break;
        }
        pump(0.01);  // keep the terminal drained so the child never blocks on it
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - signalled).count();
    while (pump(0.0)) {
    }
    close(master);
    return seconds;
}

// The heavy settings: every pixel sample draws 65536 light and 65536 BRDF samples (one
// whole pass of this film takes seconds on lavapipe, the render half a minute or more).
json heavyScene() {
    json doc = litScene(128, 96);
    doc["integrator"] = {{"type", "direct"}, {"light_samples", 65536}, {"bsdf_samples", 65536}};
    doc["sampler"]["spp"] = 8;
    return doc;
}

}  // namespace

TEST(PassBands, EveryPixelGetsEverySampleOnceInOrder) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> seconds(0.0, 0.6);
    for (uint32_t maxBands : {1u, PassBands::kMaxBandsPerSubmission})
        for (auto [width, height, spp] :
             {std::tuple{21u, 10u, 5u}, {8u, 3u, 4u}, {5u, 7u, 3u}, {64u, 9u, 2u}, {1u, 1u, 6u}}) {
            std::vector<uint32_t> next(size_t(width) * height, 0);  // the sample index each pixel expects
            PassBands bands(width, height, spp, 0, PassBands::kTile, maxBands);
            int submissions = 0;
            while (!bands.finished()) {
                ASSERT_LT(++submissions, 100000);
                const std::vector<PassBand> plan = bands.next(0.25);
                ASSERT_GE(plan.size(), 1u);
                ASSERT_LE(plan.size(), maxBands);
                std::vector<double> times;
                for (const PassBand& band : plan) {
                    // Runs of columns are whole tiles or end at the edge (a dispatch covers tiles).
                    ASSERT_EQ(band.firstColumn % PassBands::kTile, 0u);
                    ASSERT_TRUE(band.columnCount % PassBands::kTile == 0 ||
                                band.firstColumn + band.columnCount == width);
                    ASSERT_LE(band.firstRow + band.rowCount, height);
                    ASSERT_LE(band.firstColumn + band.columnCount, width);
                    ASSERT_GE(band.pixelSamples(), 1u);
                    for (uint32_t s = band.firstSample; s < band.firstSample + band.count; ++s)
                        for (uint32_t y = band.firstRow; y < band.firstRow + band.rowCount; ++y)
                            for (uint32_t x = band.firstColumn; x < band.firstColumn + band.columnCount; ++x)
                                ASSERT_EQ(next[size_t(y) * width + x]++, s) << "pixel " << x << "," << y;
                    times.push_back(seconds(rng) * double(band.pixelSamples()) / 64.0);
                }
                bands.measured(times);
                for (uint32_t v : next) EXPECT_GE(v, bands.samplesDone());
            }
            for (uint32_t v : next) EXPECT_EQ(v, spp);
        }
}

TEST(PassBands, ACapOnPixelSamplesBoundsEverySubmission) {
    // Strips of 8 rows of 16 pixels; a cap of 7 rows' pixel samples, among others, must not
    // be exceeded by a band that takes the rest of its strip.
    for (uint64_t cap : {8u, 24u, 112u, 200u}) {
        PassBands bands(16, 64, 3, cap, cap);
        while (!bands.finished()) {
            const std::vector<PassBand> plan = bands.next(0.25);
            uint64_t pixelSamples = 0;
            std::vector<double> times;
            for (const PassBand& b : plan) {
                pixelSamples += b.pixelSamples();
                times.push_back(1e-9 * double(b.pixelSamples()));
            }
            ASSERT_LE(pixelSamples, cap);
            bands.measured(times);
        }
    }
}

TEST(PassBands, ASplitPassVisitsTheFilmSpreadOut) {
    // Strips of 8 rows, first bands at rows 0, 32, 16, 48: the first submissions sample
    // the whole height of the film.
    PassBands bands(16, 64, 1);
    std::vector<uint32_t> rows;
    for (int i = 0; i < 4; ++i) {
        const std::vector<PassBand> plan = bands.next(0.25);
        ASSERT_EQ(plan.size(), 1u);  // each the size of the growing budget, within one strip
        rows.push_back(plan[0].firstRow);
        bands.measured({1e-3});
    }
    EXPECT_EQ(rows, (std::vector<uint32_t>{0, 32, 16, 48}));
}

TEST(PassBands, ASubmissionHoldsTheStripsItsBudgetCovers) {
    // A first budget of three strips' pixel samples (8 rows of 16) less a row: one
    // submission holds the first three strips of the spread order (the third strip's last
    // row comes along rather than be left for a band of its own), the next (twice the
    // pixel samples) the five left, and each band's time is its strip's cost.
    PassBands bands(16, 64, 2, 0, 3 * 8 * 16 - 16);
    auto firstRows = [](const std::vector<PassBand>& plan) {
        std::vector<uint32_t> rows;
        for (const PassBand& b : plan) {
            EXPECT_EQ(b.rowCount, 8u);
            EXPECT_EQ(b.columnCount, 16u);
            rows.push_back(b.firstRow);
        }
        return rows;
    };
    // The strip at row 32 costs 8x the others per pixel sample; a fixed 1e-4 s per band.
    auto timesOf = [](const std::vector<PassBand>& plan) {
        std::vector<double> times;
        for (const PassBand& b : plan)
            times.push_back(1e-4 + double(b.pixelSamples()) * (b.firstRow == 32 ? 8e-5 : 1e-5));
        return times;
    };
    std::vector<PassBand> plan = bands.next(0.25);
    EXPECT_EQ(firstRows(plan), (std::vector<uint32_t>{0, 32, 16}));
    bands.measured(timesOf(plan));
    plan = bands.next(0.25);
    EXPECT_EQ(firstRows(plan), (std::vector<uint32_t>{48, 8, 40, 24, 56}));
    bands.measured(timesOf(plan));
    // The second pass is sized by the costliest strip (row 32), whatever its share of the
    // submission's time: 0.25 s / 8e-5 s = 3125 pixel samples at most, and sweeps follow,
    // since a row of the costliest strip takes 1.3 ms.
    plan = bands.next(0.25);
    ASSERT_EQ(plan.size(), 1u);
    EXPECT_EQ(plan[0].firstSample, 1u);
    EXPECT_EQ(plan[0].columnCount, 16u);
    EXPECT_LE(double(plan[0].pixelSamples()) * 8e-5, 0.25);
    // A budget that leaves less than a row after a strip ends the submission there, rather
    // than add a run of a few tiles (strips of 8 rows of 64 pixels).
    PassBands rows(64, 64, 1, 0, 8 * 64 + 40);
    plan = rows.next(0.25);
    ASSERT_EQ(plan.size(), 1u);
    EXPECT_EQ(plan[0].rowCount, 8u);
    // Without timestamps each submission holds one band.
    PassBands single(16, 64, 2, 0, 3 * 8 * 16, 1);
    EXPECT_EQ(single.next(0.25).size(), 1u);
    EXPECT_THROW(single.measured({1e-3, 1e-3}), std::logic_error);
}

namespace {

// Simulated device times: per pixel sample, `cost(row)`; returns the longest submission's
// time.
double simulate(uint32_t width, uint32_t height, uint32_t spp, const std::function<double(uint32_t)>& cost,
                int* submissions = nullptr) {
    PassBands bands(width, height, spp);
    double longest = 0.0;
    int n = 0;
    while (!bands.finished()) {
        const std::vector<PassBand> plan = bands.next(0.25);
        std::vector<double> times;
        for (const PassBand& band : plan) {
            double seconds = 0.0;
            for (uint32_t y = band.firstRow; y < band.firstRow + band.rowCount; ++y)
                seconds += cost(y) * band.columnCount * band.count;
            times.push_back(seconds);
        }
        bands.measured(times);
        const double seconds = std::accumulate(times.begin(), times.end(), 0.0);
        if (n++ > 0) longest = std::max(longest, seconds);  // the first band: one tile, unknown cost
    }
    if (submissions) *submissions = n;
    return longest;
}

}  // namespace

TEST(PassBands, ABudgetLearntOnCheapPixelsIsNotSpentOnCostlyOnes) {
    // Sky above row 40 costs nothing; below, each pixel sample takes 20 ms (one row of the
    // film 2.6 s), as with 65536 light and BRDF samples. No submission may take a second.
    EXPECT_LT(simulate(128, 96, 2, [](uint32_t y) { return y < 40 ? 1e-7 : 0.02; }), 1.0);
    // The same the other way up. (A costly region smaller than a strip, below cheap rows of
    // it, can still take one band of up to twice the last band's pixels: pass_bands.h.)
    EXPECT_LT(simulate(128, 96, 2, [](uint32_t y) { return y >= 56 ? 1e-7 : 0.02; }), 1.0);
    // A cheap film soon renders whole passes, many per submission.
    int submissions = 0;
    EXPECT_LT(simulate(
                  64, 48, 4096, [](uint32_t) { return 1e-7; }, &submissions),
              0.6);
    EXPECT_LT(submissions, 100);
}

TEST(PassBands, AfterTheFirstPassSweepsGiveEachPixelAsManySamplesAsFit) {
    // Every pixel sample costs `cost`; the first pass is split, then sweeps follow.
    auto sweepBands = [](uint32_t width, uint32_t height, uint32_t spp, double cost) {
        PassBands bands(width, height, spp);
        std::vector<PassBand> sweeps;
        while (!bands.finished()) {
            const std::vector<PassBand> plan = bands.next(0.25);
            std::vector<double> times;
            for (const PassBand& band : plan) {
                if (band.firstSample > 0) sweeps.push_back(band);
                times.push_back(cost * double(band.pixelSamples()));
            }
            bands.measured(times);
        }
        return sweeps;
    };
    // Cheap: the 15 samples left go to every pixel in one sweep of whole-width row bands,
    // top to bottom, the first at most two passes' pixel samples.
    std::vector<PassBand> cheap = sweepBands(64, 48, 16, 1e-7);
    ASSERT_FALSE(cheap.empty());
    uint32_t row = 0;
    for (const PassBand& b : cheap) {
        EXPECT_EQ(b.firstSample, 1u);
        EXPECT_EQ(b.count, 15u);
        EXPECT_EQ(b.firstRow, row);
        EXPECT_EQ(b.firstColumn, 0u);
        EXPECT_EQ(b.columnCount, 64u);
        row += b.rowCount;
    }
    EXPECT_EQ(row, 48u);
    // At most four passes' pixel samples, as even those are predicted to take less than a
    // quarter of the target here (twice the pass where they are not: the costly case below).
    EXPECT_LE(cheap.front().pixelSamples(), 4u * 64 * 48);
    EXPECT_GT(cheap.front().pixelSamples(), 2u * 64 * 48);
    // Costlier: one row of one sample takes 0.077 s, so the first two sweeps give 3 samples
    // (0.23 s a row; 3 also where the estimate of a band's fixed cost, the smallest band's
    // time, lowers the costs measured by up to an eighth) in bands of one row, and the last
    // sweep the one sample left, in bands of 3 rows.
    std::vector<PassBand> costly = sweepBands(64, 48, 8, 1.2e-3);
    ASSERT_EQ(costly.size(), 2u * 48 + 16);
    for (size_t i = 0; i < costly.size(); ++i) {
        const bool last = i >= 2 * 48;
        EXPECT_EQ(costly[i].firstSample, last ? 7u : 1u + 3u * uint32_t(i / 48));
        EXPECT_EQ(costly[i].count, last ? 1u : 3u);
        EXPECT_EQ(costly[i].rowCount, last ? 3u : 1u);
        EXPECT_EQ(costly[i].firstRow, last ? 3u * uint32_t(i - 2 * 48) : uint32_t(i % 48));
        EXPECT_LE(double(costly[i].pixelSamples()) * 1.2e-3, 0.25);
    }
}

TEST(PassBands, AShortRenderTakesFewSubmissions) {
    // The time-to-error comparison's Cornell box: 200 x 200 pixels, a first band of 10,000
    // pixel samples (Renderer's first guess), 0.07 us per pixel sample. Each submission has
    // a fixed cost (0.2-0.7 ms on lavapipe, pass_bands.h), so a render of a few samples per
    // pixel should take few: the first pass in two (10,000, then the 30,000 left, since that
    // is at most half as much again as twice the first), then one sweep band of the rest
    // (up to four passes, predicted far below the target).
    const auto submissions = [](uint32_t spp) {
        PassBands bands(200, 200, spp, 0, 10000);
        std::vector<uint64_t> sizes;
        while (!bands.finished()) {
            const std::vector<PassBand> plan = bands.next(0.25);
            std::vector<double> times;
            uint64_t pixels = 0;
            for (const PassBand& b : plan) {
                times.push_back(7e-8 * double(b.pixelSamples()));
                pixels += b.pixelSamples();
            }
            sizes.push_back(pixels);
            bands.measured(times);
        }
        return sizes;
    };
    EXPECT_EQ(submissions(1), (std::vector<uint64_t>{10000, 30000}));
    EXPECT_EQ(submissions(2), (std::vector<uint64_t>{10000, 30000, 40000}));
    EXPECT_EQ(submissions(4), (std::vector<uint64_t>{10000, 30000, 120000}));
    EXPECT_EQ(submissions(5), (std::vector<uint64_t>{10000, 30000, 160000}));
    // Where the rest of the pass would not fit in the target at the cost measured (20 us per
    // pixel sample: 0.6 s), it waits: the second submission grows by x2 at most. The first
    // submission's two bands are of equal size, so the bound on a band's fixed part takes
    // all of their time and their net cost is 0; the rule goes by the gross cost.
    PassBands slow(200, 200, 1, 0, 10000);
    std::vector<double> times;
    for (const PassBand& b : slow.next(0.25)) times.push_back(2e-5 * double(b.pixelSamples()));
    ASSERT_EQ(times.size(), 2u);
    slow.measured(times);
    uint64_t second = 0;
    for (const PassBand& b : slow.next(0.25)) second += b.pixelSamples();
    EXPECT_LE(second, 20000u);
}

TEST(PassBands, SplittingARenderChangesNoPixel) {
    // A sample's value depends only on (seed, pixel, sample index) and each pixel's sum
    // receives its samples in the same order, so the bands must give identical bits.
    const gpu::Context& context = test::gpuContext();
    Scene scene = test::sceneFromJson(litScene(21, 10), "stop-bands");
    Renderer whole(context, scene);
    whole.renderAll({}, nullptr, RenderPacing{1.0, 1024 * 21 * 10});
    const Image reference = whole.readback(0);
    for (uint64_t maxPixelSamples : {1ull, 13ull, 21ull * 3 + 5, 21ull * 10 + 1}) {
        Renderer banded(context, scene);
        banded.renderAll({}, nullptr, RenderPacing{1.0, maxPixelSamples});
        EXPECT_TRUE(samePixels(banded.readback(0), reference)) << "max " << maxPixelSamples << " pixel samples";
    }
    EXPECT_TRUE(samePixels(test::renderScene(scene), reference));
}

TEST(PassBands, ProgressCountsThePixelSamplesHandedOut) {
    // Small bands, so that sweeps are part done between reports: the mean grows by each
    // band's pixel samples over the film's pixels, never falls below the samples every pixel
    // has, and ends at the spp; the seconds never go back.
    const gpu::Context& context = test::gpuContext();
    Scene scene = test::sceneFromJson(litScene(21, 10), "stop-progress");
    scene.sampler.spp = 8;
    Renderer renderer(context, scene);
    std::vector<RenderProgress> reports;
    renderer.renderAll([&](const RenderProgress& p) { reports.push_back(p); }, nullptr, RenderPacing{1.0, 21 * 4});
    ASSERT_GE(reports.size(), 2u);
    for (size_t i = 0; i < reports.size(); ++i) {
        const RenderProgress& p = reports[i];
        EXPECT_EQ(p.samplesTotal, 8u);
        EXPECT_GE(p.meanSamplesDone, double(p.samplesDone)) << i;
        EXPECT_LE(p.meanSamplesDone, double(p.samplesDone + 8)) << i;
        if (i > 0) {
            EXPECT_GT(p.meanSamplesDone, reports[i - 1].meanSamplesDone) << i;
            EXPECT_GE(p.seconds, reports[i - 1].seconds) << i;
        }
    }
    EXPECT_EQ(reports.back().samplesDone, 8u);
    EXPECT_DOUBLE_EQ(reports.back().meanSamplesDone, 8.0);
}

TEST(RenderStop, RenderStopsWithinTwoSecondsOfTheSignalWritingNothing) {
    for (int signal : {SIGINT, SIGTERM}) {
        fs::path dir = freshDir(signal == SIGINT ? "render-int" : "render-term");
        fs::path scene = dir / "heavy.json";
        std::ofstream(scene) << heavyScene().dump();
        int status = 0;
        std::string output;
        const double seconds = secondsToStop(
            {"render", scene.string(), "-o", (dir / "out.exr").string(), "--png", (dir / "out.png").string()}, signal,
            status, output);
        ASSERT_GE(seconds, 0.0) << "the render never showed progress: " << output;
        EXPECT_LT(seconds, 2.0) << strsignal(signal) << ": " << output;
        ASSERT_TRUE(WIFEXITED(status)) << output;
        EXPECT_EQ(WEXITSTATUS(status), 1) << output;
        EXPECT_NE(output.find("render interrupted"), std::string::npos) << output;
        EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 1) << "something was written: " << output;
    }
}

TEST(RenderStop, BatchStopsWithinTwoSecondsOfTheSignalWritingNothing) {
    for (int signal : {SIGTERM, SIGINT}) {
        fs::path dir = freshDir(signal == SIGINT ? "batch-int" : "batch-term");
        std::ofstream(dir / "heavy.json") << heavyScene().dump();
        json jobs = {{"jobs", {{{"scene", "heavy.json"}, {"output", "out.exr"}, {"png", true}}}}};
        std::ofstream(dir / "jobs.json") << jobs.dump();
        int status = 0;
        std::string output;
        const double seconds = secondsToStop({"batch", (dir / "jobs.json").string()}, signal, status, output);
        ASSERT_GE(seconds, 0.0) << "the batch never showed progress: " << output;
        EXPECT_LT(seconds, 2.0) << strsignal(signal) << ": " << output;
        ASSERT_TRUE(WIFEXITED(status)) << output;
        EXPECT_EQ(WEXITSTATUS(status), 1) << output;
        EXPECT_NE(output.find("interrupted, nothing written"), std::string::npos) << output;
        EXPECT_NE(output.find("batch interrupted"), std::string::npos) << output;
        EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 2) << "something was written: " << output;
    }
}
