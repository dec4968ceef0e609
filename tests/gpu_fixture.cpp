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
