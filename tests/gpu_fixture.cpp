// Shared test helpers (see gpu_fixture.h).
#include "gpu_fixture.h"

#include "gpu/buffer.h"
#include "gpu/kernel.h"

namespace penumbra::test {

gpu::Context& gpuContext() {
    static gpu::Context context;
    return context;
}

bool smokeKernelComputes(gpu::Kernel& kernel, uint32_t add) {
    const uint32_t count = 100;
    gpu::Buffer out(gpuContext(), count * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    kernel.bind(0, out);
    const uint32_t push[2] = {add, count};
    kernel.run(2, 1, 1, push);
    const auto values = out.read<uint32_t>();
    for (uint32_t i = 0; i < count; ++i)
        if (values[i] != 2 * i + add) return false;
    return true;
}

std::filesystem::path outputPath(const std::string& name) {
    std::filesystem::path dir = PENUMBRA_TEST_OUTPUT;
    std::filesystem::create_directories(dir);
    return dir / name;
}

std::filesystem::path freshOutputDir(const std::string& group, const std::string& name) {
    std::filesystem::path dir = outputPath(group) / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

// Single quotes around the path, each quote inside it closed, escaped and reopened ('\'').
// Built by appending: GCC 12 warns (-Wrestrict, a false positive) on "'" + string + "'".
std::string shellQuoted(const std::filesystem::path& path) {
    std::string quoted = "'";
    for (char c : path.string()) {
        if (c == '\'') quoted += "'\\''";
        else quoted += c;
    }
    quoted += '\'';
    return quoted;
}

}  // namespace penumbra::test
