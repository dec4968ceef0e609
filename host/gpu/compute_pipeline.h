// A compute pipeline's Vulkan objects made from SPIR-V: the shader module, the layout of
// descriptor set 0, the pipeline layout (one push-constant range) and the pipeline with its
// specialization constants. gpu::Pipeline owns what this makes for the embedded shaders; the
// micro-benchmarks (tools/bench/microbenchmarks) for SPIR-V files of their own.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace penumbra::gpu {

struct ComputePipelineObjects {
    VkShaderModule module = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
};

// The set layout and the pipeline layout alone (for kernels that are shader objects:
// gpu/shader_objects.h); failures as below.
ComputePipelineObjects createComputeLayouts(VkDevice device, const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                                            uint32_t pushConstantBytes, const std::string& what = {});

// Creates them in that order, the stage of `spirv` entered at "main" with constant_id i =
// specialization[i] (applied to the SPIR-V before the driver sees it: gpu/spirv_specialization.h). On failure destroys those already made and throws GpuError ("create
// shader module" and so on, followed by `what`, e.g. " for shader NAME").
ComputePipelineObjects createComputePipeline(VkDevice device, std::span<const uint32_t> spirv,
                                             const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                                             uint32_t pushConstantBytes, const std::vector<uint32_t>& specialization,
                                             const std::string& what = {});

// Destroys those of `objects` that exist, in the reverse order, and clears them.
void destroyComputePipeline(VkDevice device, ComputePipelineObjects& objects);

}  // namespace penumbra::gpu
