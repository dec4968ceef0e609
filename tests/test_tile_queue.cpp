// The tile queue of render dispatches (render/tile_queue.h): how many worker threads a
// device is counted to have, how many workgroups a queue gets, and that the queue renders
// every pixel's samples exactly once, for any number of workgroups and any band, so the
// image is the same bit for bit as with one workgroup per tile.
#include <gtest/gtest.h>

#include <vector>

#include "gpu_fixture.h"
#include "render/renderer.h"
#include "render/tile_queue.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;

using test::deviceWithDriver;

TEST(TileQueue, WorkerThreadsFollowLavapipes) {
    const gpu::DeviceInfo lavapipe = deviceWithDriver("llvmpipe");
    EXPECT_EQ(workerThreadsFor(lavapipe, nullptr, 2), 2u);
    EXPECT_EQ(workerThreadsFor(lavapipe, nullptr, 16), 16u);
    EXPECT_EQ(workerThreadsFor(lavapipe, nullptr, 0), 1u) << "an unknown CPU count";
    EXPECT_EQ(workerThreadsFor(lavapipe, nullptr, 500), 64u);
    EXPECT_EQ(workerThreadsFor(lavapipe, "3", 2), 3u) << "LP_NUM_THREADS decides when set";
    EXPECT_EQ(workerThreadsFor(lavapipe, "0", 8), 1u) << "LP_NUM_THREADS=0 runs on one thread";
    EXPECT_EQ(workerThreadsFor(lavapipe, "", 4), 4u);
    EXPECT_EQ(workerThreadsFor(lavapipe, "many", 4), 4u);
    EXPECT_EQ(workerThreadsFor(lavapipe, "-2", 4), 4u);
    EXPECT_EQ(workerThreadsFor(lavapipe, "4x", 6), 6u);
    EXPECT_EQ(workerThreadsFor(lavapipe, "65", 6), 6u);
    EXPECT_EQ(workerThreadsFor(deviceWithDriver("NVIDIA"), "3", 16), 1u) << "GPUs balance by themselves";
    EXPECT_EQ(workerThreadsFor(deviceWithDriver(""), nullptr, 16), 1u);
    EXPECT_FALSE(usesTileQueue(1));
    EXPECT_TRUE(usesTileQueue(2));
}

TEST(TileQueue, OneWorkgroupPerWorkerWithinTheTilesAndTheStacks) {
    EXPECT_EQ(tileQueueWorkgroups(30, 2, UINT32_MAX), 2u);
    EXPECT_EQ(tileQueueWorkgroups(uint64_t(1) << 40, 64, UINT32_MAX), 64u);
    EXPECT_EQ(tileQueueWorkgroups(1, 4, UINT32_MAX), 1u) << "a workgroup more than tiles finds the queue empty";
    EXPECT_EQ(tileQueueWorkgroups(30, 8, 5), 5u) << "the stacks' buffer bounds the workgroups";
    EXPECT_EQ(tileQueueWorkgroups(0, 2, 5), 1u);
    EXPECT_EQ(tileQueueWorkgroups(30, 2, 0), 1u);
}

TEST(TileQueue, EveryWorkerCountGivesTheSameImage) {
    // A film of 5 x 5 tiles, the last row and column partly outside, and spheres so that the
    // pixels differ.
    json doc = test::litFloorOnOddFilmScene(3, 11);
    doc["shapes"].push_back({{"type", "sphere"}, {"center", {-0.4, 0.3, 0}}, {"radius", 0.3}});
    doc["shapes"].push_back({{"type", "sphere"}, {"center", {0.5, 0.2, 0.3}}, {"radius", 0.2}});
    const Scene scene = test::sceneFromJson(doc, "tile-rows");
    struct Render {
        std::vector<gpu::AccumSum> sums;
        Image image;
    };
    auto render = [&](uint32_t workers, uint64_t maxPixelSamples) {
        Renderer renderer(test::gpuContext(), scene);
        renderer.setWorkerThreads(workers);
        RenderPacing pacing;
        pacing.maxPixelSamples = maxPixelSamples;
        renderer.renderAll({}, nullptr, pacing);
        return Render{renderer.accumulation().read<gpu::AccumSum>(), renderer.readback(0.0)};
    };
    const Render reference = render(1, 0);
    size_t lit = 0;
    for (const gpu::AccumSum& s : reference.sums) {
        EXPECT_EQ(s.count, 3u);
        lit += s.sum.x > 0.0f;
    }
    EXPECT_GT(lit, reference.sums.size() / 2) << "the light should reach most pixels";
    // One workgroup per tile above; tile queues of 2 to 7 workgroups here, over whole passes
    // and over bands of at most 200 pixel samples (runs of tiles within a row, from columns
    // past the first, and partial rows of tiles).
    for (uint32_t workers : {2u, 3u, 4u, 7u}) {
        for (uint64_t maxPixelSamples : {uint64_t(0), uint64_t(200)}) {
            SCOPED_TRACE(testing::Message() << workers << " workers, bands of at most " << maxPixelSamples);
            const Render r = render(workers, maxPixelSamples);
            ASSERT_EQ(r.sums.size(), reference.sums.size());
            size_t wrongCount = 0, differing = 0;
            for (size_t i = 0; i < r.sums.size(); ++i) {
                wrongCount += r.sums[i].count != 3u;  // a pixel rendered twice, or never
                differing += r.image.rgb[3 * i] != reference.image.rgb[3 * i] ||
                             r.image.rgb[3 * i + 1] != reference.image.rgb[3 * i + 1] ||
                             r.image.rgb[3 * i + 2] != reference.image.rgb[3 * i + 2];
            }
            EXPECT_EQ(wrongCount, 0u);
            EXPECT_EQ(differing, 0u);
        }
    }
}
