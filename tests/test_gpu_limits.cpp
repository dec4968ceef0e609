// Device limits and start-up failures: a buffer beyond maxStorageBufferRange (or the
// uniform range, or the largest allocation) is refused at creation with a message naming
// the limit and the buffer (exit 1 from the command line), and a Context whose start fails
// after the instance exists cleans up and can be created again.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/vk_check.h"
#include "gpu_fixture.h"
#include "render_helpers.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

// Runs f, expecting a GpuError whose message contains every needle.
template <class F>
void expectGpuError(F&& f, std::initializer_list<std::string> needles) {
    try {
        f();
        ADD_FAILURE() << "no GpuError";
    } catch (const gpu::GpuError& e) {
        for (const std::string& needle : needles)
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(GpuLimits, BufferSizeCheckNamesTheLimitAndTheBuffer) {
    VkPhysicalDeviceLimits limits{};
    limits.maxStorageBufferRange = 1000;
    limits.maxUniformBufferRange = 100;
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    EXPECT_NO_THROW(gpu::checkBufferSize("BVH nodes", 1000, storage, limits, 0));
    expectGpuError([&] { gpu::checkBufferSize("BVH nodes", 1001, storage, limits, 0); },
                   {"BVH nodes buffer", "1001 bytes", "maxStorageBufferRange (1000 bytes)"});
    // Transfer-only buffers (staging) are not bound: only the allocation limit applies.
    EXPECT_NO_THROW(gpu::checkBufferSize("staging", 5000, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, limits, 0));
    expectGpuError([&] { gpu::checkBufferSize("staging", 5000, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, limits, 4096); },
                   {"maxMemoryAllocationSize (4096 bytes)"});
    expectGpuError(
        [&] { gpu::checkBufferSize("render parameters", 128, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, limits, 0); },
        {"maxUniformBufferRange"});
    expectGpuError([&] { gpu::checkBufferSize("", uint64_t(3) << 30, storage, limits, 0); },
                   {"3072.0 MiB, 3221225472 bytes"});
    // Texel buffers: whole 16-byte texels, at most maxTexelBufferElements of them.
    limits.maxTexelBufferElements = 10;
    const VkBufferUsageFlags texels = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
    EXPECT_NO_THROW(gpu::checkBufferSize("BVH nodes", 175, texels, limits, 0));
    expectGpuError([&] { gpu::checkBufferSize("BVH nodes", 176, texels, limits, 0); },
                   {"BVH nodes buffer", "176 bytes", "maxTexelBufferElements (10 texels of 16 bytes)"});
}

TEST(GpuLimits, BuffersBeyondTheDeviceLimitAreRefusedAtCreation) {
    const gpu::Context& context = test::gpuContext();
    const VkDeviceSize range = context.limits().maxStorageBufferRange;
    expectGpuError([&] { gpu::Buffer(context, range + 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 0, 0, "test"); },
                   {"test buffer", "maxStorageBufferRange"});
}

TEST(GpuLimits, AFilmBeyondTheStorageLimitFailsWithExitOneNamingIt) {
    // The accumulation holds 16 bytes per pixel; films are at most 16384 x 16384.
    const uint64_t range = test::gpuContext().limits().maxStorageBufferRange;
    const uint64_t width = 16384, height = range / (16 * width) + 1;
    if (height > 16384) GTEST_SKIP() << "this device binds any film's accumulation (" << range << " bytes)";
    fs::path dir = test::outputPath("gpu-limits");
    fs::create_directories(dir);
    nlohmann::json scene = {
        {"film", {{"width", width}, {"height", height}}},
        {"sampler", {{"spp", 1}}},
        {"integrator", {{"type", "ao"}}},
        {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}}}},
    };
    std::ofstream(dir / "huge.json") << scene.dump();
    fs::remove(dir / "huge.exr");
    std::string err;
    EXPECT_EQ(
        test::runPenumbra(
            "render '" + (dir / "huge.json").string() + "' --quiet -o '" + (dir / "huge.exr").string() + "'", &err),
        1)
        << err;
    EXPECT_NE(err.find("accumulation buffer"), std::string::npos) << err;
    EXPECT_NE(err.find("maxStorageBufferRange"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(dir / "huge.exr"));
}

TEST(GpuLimits, AStartThatFailsAfterTheInstanceExistsCleansUpOnce) {
    // The instance exists when the device index is found not to exist, and when the
    // window system's surface cannot be made; both failures must leave nothing behind and
    // destroy nothing twice, and a later start works.
    for (int round = 0; round < 3; ++round) {
        gpu::ContextOptions bad;
        bad.deviceIndex = 99;
        expectGpuError([&] { gpu::Context context(bad); }, {"Vulkan device 99 does not exist"});
        gpu::ContextOptions throwing;
        VkInstance seen = VK_NULL_HANDLE;
        throwing.createSurface = [&](VkInstance instance) -> VkSurfaceKHR {
            seen = instance;
            throw gpu::GpuError("no window system");
        };
        expectGpuError([&] { gpu::Context context(throwing); }, {"no window system"});
        EXPECT_NE(seen, VK_NULL_HANDLE);
    }
    gpu::Context fine;
    EXPECT_NE(fine.device(), VK_NULL_HANDLE);
    std::string err;
    EXPECT_EQ(test::runPenumbra("devices", &err), 0) << err;
}
