// The tile-row interleave of render dispatches (render/tile_rows.h): how many slices a
// device gets, the dispatch shapes, and that every interleave renders every pixel's
// samples exactly once, so the image is the same bit for bit.
#include <gtest/gtest.h>

#include <vector>

#include "gpu_fixture.h"
#include "render/renderer.h"
#include "render/tile_rows.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;

namespace {

gpu::DeviceInfo deviceWithDriver(const std::string& driverName) {
    gpu::DeviceInfo device;
    device.driverName = driverName;
    return device;
}

}  // namespace

TEST(TileRows, SlicesFollowLavapipesWorkerThreads) {
    const gpu::DeviceInfo lavapipe = deviceWithDriver("llvmpipe");
    EXPECT_EQ(tileRowSlicesFor(lavapipe, nullptr, 2), 2u);
    EXPECT_EQ(tileRowSlicesFor(lavapipe, nullptr, 16), 16u);
    EXPECT_EQ(tileRowSlicesFor(lavapipe, nullptr, 0), 1u) << "an unknown CPU count";
    EXPECT_EQ(tileRowSlicesFor(lavapipe, nullptr, 500), 64u);
    EXPECT_EQ(tileRowSlicesFor(lavapipe, "3", 2), 3u) << "LP_NUM_THREADS decides when set";
    EXPECT_EQ(tileRowSlicesFor(lavapipe, "0", 8), 1u) << "LP_NUM_THREADS=0 runs on one thread";
    EXPECT_EQ(tileRowSlicesFor(lavapipe, "", 4), 4u);
    EXPECT_EQ(tileRowSlicesFor(lavapipe, "many", 4), 4u);
    EXPECT_EQ(tileRowSlicesFor(lavapipe, "-2", 4), 4u);
    EXPECT_EQ(tileRowSlicesFor(lavapipe, "4x", 6), 6u);
    EXPECT_EQ(tileRowSlicesFor(lavapipe, "65", 6), 6u);
    EXPECT_EQ(tileRowSlicesFor(deviceWithDriver("NVIDIA"), "3", 16), 1u) << "GPUs balance by themselves";
    EXPECT_EQ(tileRowSlicesFor(deviceWithDriver(""), nullptr, 16), 1u);
}

TEST(TileRows, DispatchCoversEveryTileRowOnce) {
    struct Case {
        uint32_t columns, rows, slices;
        DispatchShape expected;
    };
    const Case cases[] = {
        {64, 48, 2, {64, 24, 2}}, {5, 7, 3, {5, 3, 3}}, {5, 2, 8, {5, 1, 2}},
        {1, 1, 1, {1, 1, 1}},     {3, 9, 0, {3, 9, 1}}, {4, 10, 4, {4, 3, 4}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(testing::Message() << c.columns << "x" << c.rows << " tiles, " << c.slices << " slices");
        const DispatchShape shape = interleavedDispatch(c.columns, c.rows, c.slices);
        EXPECT_EQ(shape.x, c.expected.x);
        EXPECT_EQ(shape.y, c.expected.y);
        EXPECT_EQ(shape.z, c.expected.z);
        // invocationPixel's tile row for workgroup (y, z): y * Z + z.
        std::vector<int> seen(c.rows, 0);
        for (uint32_t z = 0; z < shape.z; ++z)
            for (uint32_t y = 0; y < shape.y; ++y)
                if (const uint32_t row = y * shape.z + z; row < c.rows) ++seen[row];
        for (uint32_t row = 0; row < c.rows; ++row) EXPECT_EQ(seen[row], 1) << "tile row " << row;
    }
}

TEST(TileRows, EveryInterleaveGivesTheSameImage) {
    // A film whose tile rows (5) no slice count here divides but one, and spheres so that
    // the pixels differ.
    json doc = test::litFloorOnOddFilmScene(3, 11);
    doc["shapes"].push_back({{"type", "sphere"}, {"center", {-0.4, 0.3, 0}}, {"radius", 0.3}});
    doc["shapes"].push_back({{"type", "sphere"}, {"center", {0.5, 0.2, 0.3}}, {"radius", 0.2}});
    const Scene scene = test::sceneFromJson(doc, "tile-rows");
    struct Render {
        std::vector<glm::vec4> sums;
        Image image;
    };
    auto render = [&](uint32_t slices, uint64_t maxPixelSamples) {
        Renderer renderer(test::gpuContext(), scene);
        renderer.setTileRowSlices(slices);
        RenderPacing pacing;
        pacing.maxPixelSamples = maxPixelSamples;
        renderer.renderAll({}, nullptr, pacing);
        return Render{renderer.accumulation().read<glm::vec4>(), renderer.readback(0.0)};
    };
    const Render reference = render(1, 0);
    size_t lit = 0;
    for (const glm::vec4& s : reference.sums) {
        EXPECT_EQ(s.w, 3.0f);
        lit += s.x > 0.0f;
    }
    EXPECT_GT(lit, reference.sums.size() / 2) << "the light should reach most pixels";
    for (uint32_t slices : {2u, 3u, 4u, 7u}) {
        for (uint64_t maxPixelSamples : {uint64_t(0), uint64_t(200)}) {
            SCOPED_TRACE(testing::Message() << slices << " slices, bands of at most " << maxPixelSamples);
            const Render r = render(slices, maxPixelSamples);
            ASSERT_EQ(r.sums.size(), reference.sums.size());
            size_t wrongCount = 0, differing = 0;
            for (size_t i = 0; i < r.sums.size(); ++i) {
                wrongCount += r.sums[i].w != 3.0f;  // a pixel rendered twice, or never
                differing += r.image.rgb[3 * i] != reference.image.rgb[3 * i] ||
                             r.image.rgb[3 * i + 1] != reference.image.rgb[3 * i + 1] ||
                             r.image.rgb[3 * i + 2] != reference.image.rgb[3 * i + 2];
            }
            EXPECT_EQ(wrongCount, 0u);
            EXPECT_EQ(differing, 0u);
        }
    }
}
