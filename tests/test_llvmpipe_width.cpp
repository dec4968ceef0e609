// llvmpipe's SIMD width: 16 lanes only where they were measured faster (an Intel CPU with
// AVX-512 and Mesa 25.0; host/gpu/llvmpipe_width.h), and a render process that really gets
// the width the rule gives for the driver the loader finds. Run on Debian's Mesa 22.3 and
// unstable's 26.2 too (tools/mesa/test-other-mesa), where 16 lanes rendered 60x slower and
// aborted: there the rendering process must keep 8.
#include <cstdlib>
#include <fstream>
#include <optional>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "gpu/llvmpipe_width.h"
#include "gpu_fixture.h"
#include "render_helpers.h"

using namespace penumbra;

namespace {

TEST(LlvmpipeWidth, ReadsTheMesaVersionFromTheDriverInfo) {
    const auto version = [](const std::string& info) {
        const gpu::MesaVersion v = gpu::parseMesaVersion(info);
        return std::to_string(v.major) + "." + std::to_string(v.minor);
    };
    EXPECT_EQ(version("Mesa 22.3.6 (LLVM 15.0.6)"), "22.3");
    EXPECT_EQ(version("Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"), "25.0");
    EXPECT_EQ(version("Mesa 26.1.0-devel (git-1234)"), "26.1");
    EXPECT_EQ(version("Mesa 24.10"), "24.10");
    // No version, or not Mesa's: unknown.
    for (const char* info : {"", "Mesa", "Mesa ", "Mesa 25", "Mesa 25.", "Mesa .1", "Mesa x.1", "mesa 25.0.7",
                             " Mesa 25.0.7", "580.159.04", "Mesa 123456.0", "Mesa 0.5"})
        EXPECT_FALSE(gpu::parseMesaVersion(info).known()) << '"' << info << '"';
}

TEST(LlvmpipeWidth, SixteenLanesOnlyWhereTheyWereMeasuredFaster) {
    EXPECT_TRUE(gpu::sixteenLanesPay(true, "llvmpipe", "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"));
    EXPECT_TRUE(gpu::sixteenLanesPay(true, "llvmpipe", "Mesa 25.0.2 (LLVM 19.1.7)"));
    // Mesa 22.3.6: 60x slower; 26.2.6: aborts. Other releases were not measured.
    EXPECT_FALSE(gpu::sixteenLanesPay(true, "llvmpipe", "Mesa 22.3.6 (LLVM 15.0.6)"));
    EXPECT_FALSE(gpu::sixteenLanesPay(true, "llvmpipe", "Mesa 26.2.6-1 (LLVM 22.1.8)"));
    EXPECT_FALSE(gpu::sixteenLanesPay(true, "llvmpipe", "Mesa 24.3.4 (LLVM 19.1.7)"));
    EXPECT_FALSE(gpu::sixteenLanesPay(true, "llvmpipe", "Mesa 25.1.0 (LLVM 19.1.7)"));
    EXPECT_FALSE(gpu::sixteenLanesPay(true, "llvmpipe", "Mesa 25"));
    // Not an Intel CPU with AVX-512 (AMD Zen 4 measured 0.91-1.01x), or not llvmpipe.
    EXPECT_FALSE(gpu::sixteenLanesPay(false, "llvmpipe", "Mesa 25.0.7 (LLVM 15.0.6)"));
    EXPECT_FALSE(gpu::sixteenLanesPay(true, "NVIDIA", "580.159.04"));
    EXPECT_FALSE(gpu::sixteenLanesPay(true, "radv", "Mesa 25.0.7"));
}

// The rendering process's device 0 as `penumbra devices` prints it: its name (with
// llvmpipe's width) and its driver line.
struct PrintedDevice {
    std::string driverName, driverInfo;
    int bits = 0;  // llvmpipe's SIMD width in bits; 0 for other devices
};
PrintedDevice printedDevice0() {
    std::string out;
    if (test::runPenumbra("devices", nullptr, &out) != 0) return {};
    std::smatch match;
    PrintedDevice device;
    if (std::regex_search(out, match, std::regex(R"(\* 0: llvmpipe \(LLVM [^,]*, (\d+) bits\))")))
        device.bits = std::stoi(match[1]);
    if (std::regex_search(out, match, std::regex(R"(\* 0: [^\n]*\n    driver: ([^,\n]*), ([^;\n]*))"))) {
        device.driverName = match[1];
        device.driverInfo = match[2];
    }
    return device;
}

TEST(LlvmpipeWidth, TheRenderingProcessGetsTheWidthTheRuleGivesForItsDriver) {
    for (const char* user : {"LP_NATIVE_VECTOR_WIDTH", "MESA_SHADER_CACHE_DIR", "PENUMBRA_DEVICE"}) {
        if (std::getenv(user) != nullptr) GTEST_SKIP() << user << " is set: the choice is the user's";
    }
    const PrintedDevice device = printedDevice0();
    ASSERT_FALSE(device.driverName.empty()) << "penumbra devices printed no driver for device 0";
    if (device.driverName != "llvmpipe") GTEST_SKIP() << "device 0 is " << device.driverName << ", not llvmpipe";
    ASSERT_GT(device.bits, 0) << "llvmpipe's name gave no width";
    const gpu::MesaVersion version = gpu::parseMesaVersion(device.driverInfo);
    ASSERT_TRUE(version.known()) << device.driverInfo;
    // Outside Mesa 25.0, never 16 lanes, whatever the CPU: a wrong rule or a choice made
    // before the driver's version is known would give 512 here on an Intel CPU with AVX-512.
    if (version.major != 25 || version.minor != 0) {
        EXPECT_EQ(device.bits, 256) << device.driverInfo;
    }
    const bool pays = gpu::sixteenLanesPay(gpu::cpuIsIntelWithAvx512(), device.driverName, device.driverInfo);
    EXPECT_EQ(device.bits, pays ? 512 : 256) << device.driverInfo;
}

TEST(LlvmpipeWidth, AnUnusableCacheDirectoryKeepsEightLanes) {
    // XDG_CACHE_HOME naming a file: the 16-lane kernels would have no cache of their own
    // (Mesa disables it and every start compiles them again), so the choice keeps 8 lanes,
    // whatever the CPU and driver. The child processes inherit the variable from this one.
    for (const char* user : {"LP_NATIVE_VECTOR_WIDTH", "MESA_SHADER_CACHE_DIR", "PENUMBRA_DEVICE"}) {
        if (std::getenv(user) != nullptr) GTEST_SKIP() << user << " is set: the choice is the user's";
    }
    const std::string file = test::outputPath("not-a-cache-directory").string();
    std::ofstream(file) << "a file, not a directory\n";
    const char* before = std::getenv("XDG_CACHE_HOME");
    const std::optional<std::string> saved = before ? std::optional<std::string>(before) : std::nullopt;
    setenv("XDG_CACHE_HOME", file.c_str(), 1);
    const PrintedDevice device = printedDevice0();
    if (saved) {
        setenv("XDG_CACHE_HOME", saved->c_str(), 1);
    } else {
        unsetenv("XDG_CACHE_HOME");
    }
    ASSERT_FALSE(device.driverName.empty()) << "penumbra devices printed no driver for device 0";
    if (device.driverName != "llvmpipe") GTEST_SKIP() << "device 0 is " << device.driverName << ", not llvmpipe";
    EXPECT_EQ(device.bits, 256) << device.driverInfo;
}

}  // namespace
