// Shared test helpers: one lavapipe Context for the whole test binary, and where tests
// write what a human may want to look at after a failure (build/test-output/).
#pragma once

#include <filesystem>
#include <string>

#include "gpu/context.h"

namespace penumbra::test {

// The process-wide GPU context (created on first use, lives until exit).
gpu::Context& gpuContext();

// build/test-output/<name>, with the directory created.
std::filesystem::path outputPath(const std::string& name);

// build/test-output/<group>/<name>, emptied and created.
std::filesystem::path freshOutputDir(const std::string& group, const std::string& name);

// A device known only by its driver's name and version string (VkPhysicalDeviceDriverProperties),
// for the rules that choose by them.
inline gpu::DeviceInfo deviceWithDriver(const std::string& driverName, const std::string& driverInfo = "") {
    gpu::DeviceInfo info;
    info.driverName = driverName;
    info.driverInfo = driverInfo;
    return info;
}

}  // namespace penumbra::test
namespace penumbra::gpu {
class Kernel;
}  // namespace penumbra::gpu
namespace penumbra::test {

// Runs the tests/smoke kernel (out[i] = 2 i + add over 100 values, binding 0, push {add,
// count}) and checks every value: a pipeline or shader object shared, dropped or loaded
// from disk still computes.
bool smokeKernelComputes(gpu::Kernel& kernel, uint32_t add);

// `path` in single quotes for a shell command line (test paths hold no quotes).
std::string shellQuoted(const std::filesystem::path& path);

}  // namespace penumbra::test
