// The SIMD width llvmpipe compiles kernels for (see llvmpipe_width.h).
#include "gpu/llvmpipe_width.h"

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace penumbra::gpu {

namespace {

constexpr const char* kWidth = "LP_NATIVE_VECTOR_WIDTH";
constexpr const char* kCacheDir = "MESA_SHADER_CACHE_DIR";
constexpr const char* kMarker = "PENUMBRA_LLVMPIPE_WIDTH";  // set beside the two: penumbra chose them

// The Mesa release series whose llvmpipe was measured faster with 16 lanes (25.0.7). The
// others keep 8 until measured: 22.3.6 rendered 60x slower, and 26.2.6 (Debian unstable's)
// aborts with "stack smashing detected" on a scene with a BVH; a release in between may be
// either.
constexpr MesaVersion kFastMesa{25, 0};

// Where the 16-lane kernels are cached; empty when there is no home to put it in.
std::string sixteenLaneCache() {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && xdg[0] == '/')
        return std::string(xdg) + "/penumbra/llvmpipe-512";
    if (const char* home = std::getenv("HOME"); home != nullptr && home[0] == '/')
        return std::string(home) + "/.cache/penumbra/llvmpipe-512";
    return {};
}

// Whether `dir` is a directory, made if missing. Where it cannot be (a file on the way, no
// permission, a path too long), Mesa would disable its cache with a warning on stderr, and
// every start would compile the kernels again: 8 lanes with the usual cache serve better.
bool usableDirectory(const std::string& dir) {
    if (dir.empty()) return false;
    std::error_code error;
    std::filesystem::create_directories(dir, error);
    return std::filesystem::is_directory(dir, error) && !error;
}

// Reads a decimal number of at most 4 digits at `text[*at]`; -1 if there is none.
int readNumber(const std::string& text, size_t* at) {
    int value = 0, digits = 0;
    while (*at < text.size() && text[*at] >= '0' && text[*at] <= '9' && digits < 4) {
        value = value * 10 + (text[*at] - '0');
        ++*at;
        ++digits;
    }
    return digits > 0 ? value : -1;
}

}  // namespace

MesaVersion parseMesaVersion(const std::string& driverInfo) {
    const std::string prefix = "Mesa ";
    if (driverInfo.compare(0, prefix.size(), prefix) != 0) return {};
    size_t at = prefix.size();
    const int major = readNumber(driverInfo, &at);
    if (major <= 0 || at >= driverInfo.size() || driverInfo[at] != '.') return {};
    ++at;
    const int minor = readNumber(driverInfo, &at);
    if (minor < 0) return {};
    return {major, minor};
}

bool sixteenLanesPay(bool intelWithAvx512, const std::string& driverName, const std::string& driverInfo) {
    if (!intelWithAvx512 || driverName != "llvmpipe") return false;
    const MesaVersion version = parseMesaVersion(driverInfo);
    if (!version.known()) return false;
    return version.major == kFastMesa.major && version.minor == kFastMesa.minor;
}

bool cpuIsIntelWithAvx512() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_is("intel");
#else
    return false;
#endif
}

bool llvmpipeWidthChoiceOpen(bool presents) {
    static bool chosenHere = false;
    if (chosenHere) return false;
    chosenHere = true;
    if (std::getenv(kMarker) != nullptr) {  // a penumbra that started this one chose them
        unsetenv(kWidth);
        unsetenv(kCacheDir);
        unsetenv(kMarker);
    }
    if (presents || std::getenv(kWidth) != nullptr || std::getenv(kCacheDir) != nullptr) return false;
    return cpuIsIntelWithAvx512() && usableDirectory(sixteenLaneCache());
}

void askForSixteenLanes() {
    setenv(kCacheDir, sixteenLaneCache().c_str(), 1);
    setenv(kWidth, "512", 1);
    setenv(kMarker, "512", 1);
}

}  // namespace penumbra::gpu
