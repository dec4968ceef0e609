// Shared test helpers (see gpu_fixture.h).
#include "gpu_fixture.h"

namespace penumbra::test {

gpu::Context& gpuContext() {
    static gpu::Context context;
    return context;
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

std::string shellQuoted(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

}  // namespace penumbra::test
