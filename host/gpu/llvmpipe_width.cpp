// The SIMD width llvmpipe compiles kernels for (see llvmpipe_width.h).
#include "gpu/llvmpipe_width.h"

#include <cstdlib>
#include <string>

namespace penumbra::gpu {

namespace {

constexpr const char* kWidth = "LP_NATIVE_VECTOR_WIDTH";
constexpr const char* kCacheDir = "MESA_SHADER_CACHE_DIR";
constexpr const char* kMarker = "PENUMBRA_LLVMPIPE_WIDTH";  // set beside the two: penumbra chose them

bool cpuRunsSixteenLanesFaster() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_is("intel");
#else
    return false;
#endif
}

// Where the 16-lane kernels are cached; empty when there is no home to put it in.
std::string sixteenLaneCache() {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && xdg[0] == '/')
        return std::string(xdg) + "/penumbra/llvmpipe-512";
    if (const char* home = std::getenv("HOME"); home != nullptr && home[0] == '/')
        return std::string(home) + "/.cache/penumbra/llvmpipe-512";
    return {};
}

}  // namespace

void chooseLlvmpipeVectorWidth(bool presents) {
    static bool chosenHere = false;
    if (chosenHere) return;
    chosenHere = true;
    if (std::getenv(kMarker) != nullptr) {  // a penumbra that started this one chose them
        unsetenv(kWidth);
        unsetenv(kCacheDir);
        unsetenv(kMarker);
    }
    if (presents || std::getenv(kWidth) != nullptr || std::getenv(kCacheDir) != nullptr) return;
    if (!cpuRunsSixteenLanesFaster()) return;
    const std::string cache = sixteenLaneCache();
    if (cache.empty()) return;
    setenv(kCacheDir, cache.c_str(), 1);
    setenv(kWidth, "512", 1);
    setenv(kMarker, "512", 1);
}

}  // namespace penumbra::gpu
