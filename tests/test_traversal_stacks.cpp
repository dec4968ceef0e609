// The "_address" kernels' traversal stacks (render/traversal_stacks.h): the buffer's size,
// dispatches that stay within it, and that a band split into several dispatches, or given
// to a tile queue, renders every pixel's samples once, the same image bit for bit as the
// kernels whose stack is a local array.
#include <gtest/gtest.h>

#include <vector>

#include "gpu_fixture.h"
#include "render/renderer.h"
#include "render/traversal_stacks.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;

TEST(TraversalStacks, HoldTheFilmUpToTheLimitAndAlwaysOneRow) {
    EXPECT_EQ(stackInvocationsFor(64, 48), 64u * 48u * 64u);      // a 512 x 384 film
    EXPECT_EQ(stackInvocationsFor(480, 270), kStackInvocations);  // 3840 x 2160
    EXPECT_EQ(stackInvocationsFor(5, 5, 1), 5u * 64u);
    EXPECT_EQ(stackInvocationsFor(10000, 4), 10000u * 64u);  // one row of a very wide film
    EXPECT_EQ(stackInvocationsFor(0, 0), 64u);
    // The limit keeps the buffer within kStackBytes for deep trees' stacks.
    EXPECT_EQ(stackInvocationLimit(45), kStackInvocations);
    // The 1M-triangle bench scene's two stacks of 45 entries per invocation.
    EXPECT_EQ(stackInvocationLimit(gpu::BVH_STACKS_PER_INVOCATION * 45), 186413u);
    EXPECT_EQ(stackInvocationLimit(64), kStackInvocations);
    EXPECT_EQ(stackInvocationLimit(3 * BVH_MAX_DEPTH), 87381u);
    EXPECT_LE(uint64_t(stackInvocationLimit(3 * BVH_MAX_DEPTH)) * 3 * BVH_MAX_DEPTH * 4, kStackBytes);
    EXPECT_EQ(stackInvocationLimit(0xffffffffu), 1u);
}

TEST(TraversalStacks, DispatchesFitAndAreAsLargeAsFits) {
    for (uint32_t columns : {1u, 5u, 64u})
        for (uint32_t invocations : {64u * columns, 64u * columns * 3u + 17u, 64u * columns * 40u}) {
            SCOPED_TRACE(testing::Message() << columns << " columns, " << invocations);
            const uint32_t rows = tileRowsPerDispatch(columns, invocations);
            ASSERT_GE(rows, 1u);
            EXPECT_LE(invocationsOf(uint64_t(columns) * rows), invocations);
            EXPECT_GT(invocationsOf(uint64_t(columns) * (rows + 1)), invocations);
        }
    EXPECT_EQ(tileRowsPerDispatch(5, 1), 1u) << "never less than one row";
}

TEST(TraversalStacks, SplitBandsGiveTheSameImage) {
    // Five tile rows, and spheres enough for a tree whose traversals push nodes.
    json doc = test::litFloorOnOddFilmScene(3, 5);
    for (int i = 0; i < 40; ++i)
        doc["shapes"].push_back({{"type", "sphere"},
                                 {"center", {-0.9 + 0.045 * i, 0.1 + 0.05 * (i % 4), 0.03 * i - 0.6}},
                                 {"radius", 0.05 + 0.02 * (i % 5)}});
    const Scene scene = test::sceneFromJson(doc, "traversal-stacks");
    auto render = [&](NodeReads reads, uint32_t workers, uint32_t stackInvocations) {
        Renderer renderer(test::gpuContext(), scene);
        renderer.setInlineGeometry(InlineGeometry::Off);
        renderer.setNodeReads(reads);
        renderer.setWorkerThreads(workers);
        if (stackInvocations) renderer.setStackInvocations(stackInvocations);
        renderer.renderAll();
        return std::make_pair(renderer.accumulation().read<gpu::AccumSum>(), renderer.readback(0.0));
    };
    const auto [referenceSums, reference] = render(NodeReads::Texels, 1, 0);
    size_t shadowed = 0;
    for (const gpu::AccumSum& s : referenceSums) shadowed += s.sum.x == 0.0f;
    EXPECT_GT(shadowed, 0u) << "the spheres should shadow part of the floor";
    ASSERT_TRUE(test::gpuContext().info().shaderInt64 && test::gpuContext().info().bufferDeviceAddress)
        << "the test device should read nodes through their address";
    // One workgroup per tile (1 worker) with stacks for 0: the film, one dispatch per band;
    // 1: one row of tiles (5 x 64 invocations), five dispatches; 700: two rows, three. A tile
    // queue (3 or 7 workers) is one dispatch of at most 3, 7 or, with stacks for one row, 5
    // workgroups.
    for (uint32_t workers : {1u, 3u, 7u})
        for (uint32_t stackInvocations : {0u, 1u, 700u}) {
            SCOPED_TRACE(testing::Message() << workers << " workers, stacks for " << stackInvocations);
            const auto [sums, image] = render(NodeReads::Address, workers, stackInvocations);
            ASSERT_EQ(sums.size(), referenceSums.size());
            size_t wrongCount = 0, differing = 0;
            for (size_t i = 0; i < sums.size(); ++i) wrongCount += sums[i].count != 3u;  // twice, or never
            for (size_t i = 0; i < image.rgb.size(); ++i) differing += image.rgb[i] != reference.rgb[i];
            EXPECT_EQ(wrongCount, 0u);
            EXPECT_EQ(differing, 0u);
        }
}
