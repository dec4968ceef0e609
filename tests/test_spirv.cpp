// Every embedded shader is valid SPIR-V for Vulkan 1.1 (spirv-val from Debian's
// spirv-tools). Lavapipe runs some invalid modules anyway; real drivers may not.
#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "gpu/shaders.h"
#include "gpu_fixture.h"

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
