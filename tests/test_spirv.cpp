// Every embedded shader is valid SPIR-V for Vulkan 1.1 (spirv-val from Debian's
// spirv-tools), before and after its specialization constants are applied on the host
// (gpu/spirv_specialization.h). Lavapipe runs some invalid modules anyway; real drivers may not.
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu/shaders.h"
#include "gpu/spirv_specialization.h"
#include "gpu_fixture.h"
#include "render/kernel_options.h"
#include "render/node_reads.h"

using namespace penumbra;

TEST(Spirv, EveryEmbeddedShaderValidates) {
    if (std::system("command -v spirv-val >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "spirv-val not installed (Debian package spirv-tools; tools/setup installs it)";
    auto names = shaderNames();
    ASSERT_FALSE(names.empty());
    for (std::string_view name : names) {
        std::string file = test::outputPath("spirv-" + std::string(name).replace(std::string(name).find('/'), 1, "-") + ".spv");
        auto code = shaderCode(name);
        std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(code.data()), code.size_bytes());
        std::string cmd = "spirv-val --target-env vulkan1.1 '" + file + "' 2>&1";
        EXPECT_EQ(std::system(cmd.c_str()), 0) << name << " is not valid SPIR-V";
    }
}

namespace {

// How many OpSpecConstant* instructions (opcodes 48-52, SPIR-V 1.6 section 3.56.13) a
// module holds: the word after the 5-word header starts each instruction, its high half
// the instruction's length.
size_t specConstants(const std::vector<uint32_t>& code) {
    size_t count = 0;
    for (size_t i = 5; i < code.size(); i += std::max<uint32_t>(code[i] >> 16, 1)) {
        const uint32_t opcode = code[i] & 0xffff;
        count += opcode >= 48 && opcode <= 52;
    }
    return count;
}

bool validates(const std::vector<uint32_t>& code, const std::string& name) {
    std::string file = test::outputPath("spirv-specialized-" + name + ".spv");
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(code.data()), std::streamsize(code.size() * sizeof(uint32_t)));
    std::string cmd = "spirv-val --target-env vulkan1.1 '" + file + "' 2>&1";
    return std::system(cmd.c_str()) == 0;
}

}  // namespace

TEST(Spirv, SpecializedShadersHaveNoSpecConstantsLeftAndValidate) {
    if (std::system("command -v spirv-val >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "spirv-val not installed (Debian package spirv-tools; tools/setup installs it)";
    // Every shader at its defaults, and the direct kernel as the Cornell box makes it.
    for (std::string_view name : shaderNames()) {
        const auto code = shaderCode(name);
        const std::vector<uint32_t> frozen = gpu::specializeSpirv(code, {});
        std::string file(name);
        std::replace(file.begin(), file.end(), '/', '-');
        EXPECT_EQ(specConstants(frozen), 0u) << name;
        EXPECT_LE(frozen.size(), code.size()) << name;
        EXPECT_TRUE(validates(frozen, file)) << name;
    }
}

TEST(Spirv, TheSpecializationValuesDecideTheCode) {
    // Two strategies of the direct kernel make different code; the same values the same.
    KernelOptions light;
    light.integrator.strategy = Strategy::Light;
    KernelOptions mis = light;
    mis.integrator.strategy = Strategy::Mis;
    const auto code = shaderCode(nodeReadsKernel("integrators/direct", light.nodeReads));
    const auto a = gpu::specializeSpirv(code, light.specialization());
    const auto b = gpu::specializeSpirv(code, mis.specialization());
    EXPECT_NE(a, b);
    EXPECT_EQ(a, gpu::specializeSpirv(code, light.specialization()));
    // Light sampling alone needs no BRDF sampling or MIS weights: less code than MIS.
    EXPECT_LT(a.size(), b.size());
}
