// Specialization before the driver (see spirv_specialization.h).
#include "gpu/spirv_specialization.h"

#include <spirv-tools/optimizer.hpp>

#include <string>
#include <unordered_map>

#include "gpu/vk_check.h"

namespace penumbra::gpu {

std::vector<uint32_t> specializeSpirv(std::span<const uint32_t> code, const std::vector<uint32_t>& values) {
    std::unordered_map<uint32_t, std::vector<uint32_t>> bits;
    for (uint32_t id = 0; id < values.size(); ++id) bits[id] = {values[id]};
    std::string diagnostics;
    spvtools::Optimizer optimizer(SPV_ENV_VULKAN_1_1);
    optimizer.SetMessageConsumer([&](spv_message_level_t level, const char*, const spv_position_t&, const char* text) {
        if (level <= SPV_MSG_ERROR) diagnostics += std::string(text) + "; ";
    });
    // The values, then constants instead of spec constants, then the expressions of them
    // (OpSpecConstantOp) folded, so that every branch a constant decides has a constant
    // condition; then those branches, the functions no longer called and the code no
    // longer used, removed; blocks left in a straight line are merged.
    optimizer.RegisterPass(spvtools::CreateSetSpecConstantDefaultValuePass(bits))
        .RegisterPass(spvtools::CreateFreezeSpecConstantValuePass())
        .RegisterPass(spvtools::CreateFoldSpecConstantOpAndCompositePass())
        .RegisterPass(spvtools::CreateCCPPass())
        .RegisterPass(spvtools::CreateDeadBranchElimPass())
        .RegisterPass(spvtools::CreateEliminateDeadFunctionsPass())
        .RegisterPass(spvtools::CreateAggressiveDCEPass())
        .RegisterPass(spvtools::CreateBlockMergePass());
    spvtools::OptimizerOptions options;
    options.set_run_validator(false);  // the embedded modules were validated when built
    std::vector<uint32_t> out;
    if (!optimizer.Run(code.data(), code.size(), &out, options))
        throw GpuError("specializing SPIR-V failed: " + diagnostics);
    return out;
}

}  // namespace penumbra::gpu
