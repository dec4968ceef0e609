// gpu::KernelCache: a pipeline per distinct request, shared by later equal requests, and
// at most maxPipelines held, the least recently requested dropped first. The smallest
// test shader stands in for the render kernels: a specialization entry whose constant_id
// the shader does not declare changes nothing in it (Vulkan 1.3, 10.9 "Specialization
// Constants"), but it is part of the cache's key, so each value is a distinct pipeline.
#include <cstdint>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "gpu/kernel_cache.h"
#include "gpu_fixture.h"

using namespace penumbra;

namespace {

const std::vector<VkDescriptorType> kSmokeBindings = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};

std::unique_ptr<gpu::Kernel> request(gpu::KernelCache& cache, uint32_t variant) {
    return cache.kernel("tests/smoke", kSmokeBindings, 8, {variant});
}

}  // namespace

TEST(KernelCache, EqualRequestsShareOnePipeline) {
    gpu::KernelCache cache(test::gpuContext());
    auto a = request(cache, 1), b = request(cache, 1), c = request(cache, 2);
    EXPECT_EQ(cache.pipelinesCreated(), 2u);
    EXPECT_EQ(cache.pipelinesReused(), 1u);
    EXPECT_EQ(&a->pipeline(), &b->pipeline());
    EXPECT_NE(&a->pipeline(), &c->pipeline());
    EXPECT_TRUE(test::smokeKernelComputes(*b, 3));
}

TEST(KernelCache, HoldsAtMostItsLimitDroppingTheLeastRecentlyRequested) {
    const size_t limit = 3;
    gpu::KernelCache cache(test::gpuContext(), limit);
    auto first = request(cache, 0);
    for (uint32_t v = 1; v < 3; ++v) request(cache, v);  // 0, 1, 2 held
    request(cache, 0);                                   // 0 is now the most recent
    EXPECT_EQ(cache.pipelinesReused(), 1u);
    request(cache, 3);  // drops 1, the least recently requested
    EXPECT_EQ(cache.pipelinesHeld(), limit);
    EXPECT_EQ(cache.pipelinesCreated(), 4u);
    request(cache, 0);
    request(cache, 2);
    request(cache, 3);
    EXPECT_EQ(cache.pipelinesCreated(), 4u) << "0, 2 and 3 are still held";
    EXPECT_EQ(cache.pipelinesReused(), 4u);
    request(cache, 1);
    EXPECT_EQ(cache.pipelinesCreated(), 5u) << "1 was dropped, so it is compiled again";
    EXPECT_EQ(cache.pipelinesHeld(), limit);
    // A kernel outlives its pipeline's place in the cache: 0 was dropped by the request for 1.
    for (uint32_t v = 10; v < 10 + limit; ++v) request(cache, v);
    EXPECT_EQ(cache.pipelinesHeld(), limit);
    EXPECT_TRUE(test::smokeKernelComputes(*first, 3));
}
