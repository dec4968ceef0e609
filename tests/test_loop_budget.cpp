// Drivers that end a shader's loops early (render/loop_budget.h): which devices the kernels
// check for it, that a pixel left short takes its samples up where it stopped, and that a
// render whose loops the driver cuts still gives every pixel every sample, the same image bit
// for bit as one whose loops are whole.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gpu_fixture.h"
#include "render/loop_budget.h"
#include "render/renderer.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;

namespace {

// The odd film with two spheres, so that the pixels differ. The renders that must loop long
// trace it through the BVH: inline primitives would leave the traversal's loops out.
Scene sceneWithSpheres(uint32_t spp) {
    json doc = test::litFloorOnOddFilmScene(spp, 5);
    doc["shapes"].push_back({{"type", "sphere"}, {"center", {-0.4, 0.3, 0}}, {"radius", 0.3}});
    doc["shapes"].push_back({{"type", "sphere"}, {"center", {0.5, 0.2, 0.3}}, {"radius", 0.2}});
    return test::sceneFromJson(doc, "loop-budget");
}

struct Render {
    std::vector<gpu::AccumSum> sums;
    Image image;
};

Render result(const Renderer& renderer) {
    return {renderer.accumulation().read<gpu::AccumSum>(), renderer.readback(0.0)};
}

// Pixels whose sample count is not `spp`, and pixels whose image values differ from `reference`.
void expectSameRender(const Render& r, const Render& reference, uint32_t spp) {
    ASSERT_EQ(r.sums.size(), reference.sums.size());
    size_t wrongCount = 0, differing = 0;
    for (size_t i = 0; i < r.sums.size(); ++i) {
        wrongCount += r.sums[i].count != spp;
        for (int c = 0; c < 3; ++c) differing += r.image.rgb[3 * i + c] != reference.image.rgb[3 * i + c];
    }
    EXPECT_EQ(wrongCount, 0u);
    EXPECT_EQ(differing, 0u);
}

}  // namespace

TEST(LoopBudget, OldLavapipesAreChecked) {
    EXPECT_TRUE(loopsMayBeCutFor(test::deviceWithDriver("llvmpipe", "Mesa 22.3.6 (LLVM 15.0.6)"))) << "measured to cut";
    EXPECT_TRUE(loopsMayBeCutFor(test::deviceWithDriver("llvmpipe", "Mesa 24.2.8-1 (LLVM 19.1.4)")))
        << "not measured: checked";
    EXPECT_TRUE(loopsMayBeCutFor(test::deviceWithDriver("llvmpipe", ""))) << "a version it does not name: checked";
    EXPECT_FALSE(loopsMayBeCutFor(test::deviceWithDriver("llvmpipe", "Mesa 25.0.7-1~bpo12+1 (LLVM 15.0.6)")))
        << "measured whole";
    EXPECT_FALSE(loopsMayBeCutFor(test::deviceWithDriver("llvmpipe", "Mesa 26.0.1 (LLVM 19.1.7)")));
    EXPECT_FALSE(loopsMayBeCutFor(test::deviceWithDriver("NVIDIA", "580.95.05")));
    EXPECT_FALSE(loopsMayBeCutFor(test::deviceWithDriver("radv", "Mesa 22.3.6"))) << "only llvmpipe has the limit";
}

TEST(LoopBudget, APixelLeftShortTakesUpItsSamplesWhereItStopped) {
    // With the checks on, a pass starts each pixel at its own count: the top two rows of
    // tiles get samples 0-2 first, then a pass of samples 0-7 over the whole film gives them
    // 3-7 and every other pixel 0-7. Without that, the top rows would get 0-2 twice. Both
    // sample loops: the primitives inline, and the BVH (where the device's kernels trace
    // rays in pairs, direct.comp's own loop).
    const Scene scene = sceneWithSpheres(8);
    for (InlineGeometry geometry : {InlineGeometry::Rule, InlineGeometry::Off}) {
        Renderer whole(test::gpuContext(), scene);
        whole.setInlineGeometry(geometry);
        whole.setWorkerThreads(1);
        whole.setLoopChecks(false);
        test::gpuContext().submitAndWait([&](VkCommandBuffer cmd) { whole.recordPasses(cmd, 0, 8, 0, 35); });
        const Render reference = result(whole);
        for (uint32_t workers : {1u, 2u}) {
            SCOPED_TRACE(testing::Message()
                         << workers << " workers, inline " << (geometry == InlineGeometry::Off ? "off" : "by rule"));
            Renderer resumed(test::gpuContext(), scene);
            resumed.setInlineGeometry(geometry);
            resumed.setWorkerThreads(workers);
            resumed.setLoopChecks(true);
            test::gpuContext().submitAndWait([&](VkCommandBuffer cmd) {
                resumed.recordPasses(cmd, 0, 3, 0, 16);
                resumed.recordPasses(cmd, 0, 8, 0, 35);
            });
            expectSameRender(result(resumed), reference, 8u);
        }
    }
}

TEST(LoopBudget, CutLoopsLeaveNoSampleOut) {
    // 2048 samples, each of four light and four BRDF samples, of 37 x 35 pixels in one
    // dispatch: on lavapipe 22.3 some SIMD groups run out of loop iterations before their
    // pixels have every sample (368 invocations measured), so the render cuts loops and
    // renderAll must render what they left. The reference adds 64 samples per pixel per
    // dispatch over the whole film, one pixel per invocation, with the checks off: an eighth
    // of the 512 that 22.3 rendered in one dispatch without a cut, and every pixel must have
    // every sample. (renderAll's bands would not do: within a bound on pixel samples, a band
    // of few rows may take many samples.)
    const uint32_t spp = 2048;
    json doc = test::litFloorOnOddFilmScene(spp, 5);
    doc["integrator"]["light_samples"] = 4;
    doc["integrator"]["bsdf_samples"] = 4;
    doc["shapes"].push_back({{"type", "sphere"}, {"center", {-0.4, 0.3, 0}}, {"radius", 0.3}});
    const Scene scene = test::sceneFromJson(doc, "loop-budget-cut");
    Renderer inSteps(test::gpuContext(), scene);
    inSteps.setInlineGeometry(InlineGeometry::Off);
    inSteps.setLoopChecks(false);
    inSteps.setWorkerThreads(1);  // one pixel per invocation: no tile queue, whose loops run long
    for (uint32_t first = 0; first < spp; first += 64)
        test::gpuContext().submitAndWait([&](VkCommandBuffer cmd) { inSteps.recordPasses(cmd, first, 64, 0, 35); });
    const Render reference = result(inSteps);
    for (const gpu::AccumSum& s : reference.sums) ASSERT_EQ(s.count, spp) << "the reference lost samples";
    for (bool forced : {false, true}) {
        SCOPED_TRACE(forced ? "checks on" : "checks as the device needs");
        Renderer once(test::gpuContext(), scene);
        once.setInlineGeometry(InlineGeometry::Off);
        if (forced) once.setLoopChecks(true);
        once.renderAll({}, nullptr, RenderPacing{1000.0, 0});  // one band: every sample at once
        expectSameRender(result(once), reference, spp);
        // Where the driver cuts (22.3), the test must have made it cut, or it shows nothing.
        if (loopsMayBeCutFor(test::gpuContext().info()))
            EXPECT_GT(once.loopCuts(), 0u) << "the render stayed within the driver's loop budget";
        else EXPECT_EQ(once.loopCuts(), 0u);
    }
}
