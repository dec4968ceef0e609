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

}  // namespace penumbra::test
