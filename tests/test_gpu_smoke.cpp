// The GPU plumbing itself: an embedded shader runs on lavapipe and its output reads back.
#include <gtest/gtest.h>

#include "gpu/kernel.h"
#include "gpu_fixture.h"

using namespace penumbra;

TEST(GpuSmoke, KernelWritesBufferWithPushConstants) {
    auto& ctx = test::gpuContext();
    const uint32_t count = 1000;
    gpu::Buffer out(ctx, count * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    gpu::Kernel kernel(ctx, "tests/smoke", {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, 8);
    kernel.bind(0, out);
    uint32_t push[2] = {7, count};
    kernel.run((count + 63) / 64, 1, 1, push);
    auto values = out.read<uint32_t>();
    for (uint32_t i = 0; i < count; ++i) ASSERT_EQ(values[i], 2 * i + 7) << "at " << i;
}
