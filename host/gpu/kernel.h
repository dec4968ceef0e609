// One compute pipeline with its descriptor set: the embedded shader, the descriptor
// types of bindings 0..n-1 of set 0, an optional push-constant block, and optional
// specialization constants (constant_id i = specialization[i]).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/context.h"

namespace penumbra::gpu {

class Kernel {
public:
    Kernel(const Context& context, std::string_view shaderName, std::vector<VkDescriptorType> bindings,
           uint32_t pushConstantBytes = 0, std::vector<uint32_t> specialization = {});
    ~Kernel();
    Kernel(const Kernel&) = delete;
    Kernel& operator=(const Kernel&) = delete;

    // Points `binding` at the whole of `buffer` (kept by handle: the buffer must outlive use).
    void bind(uint32_t binding, const Buffer& buffer);

    // Records a dispatch of `groups` workgroups; `push` must hold pushConstantBytes bytes.
    void record(VkCommandBuffer cmd, uint32_t groupsX, uint32_t groupsY = 1, uint32_t groupsZ = 1,
                const void* push = nullptr) const;
    // Dispatches once and waits for the result.
    void run(uint32_t groupsX, uint32_t groupsY = 1, uint32_t groupsZ = 1, const void* push = nullptr) const;

private:
    const Context& m_context;
    std::string m_name;
    std::vector<VkDescriptorType> m_bindings;
    uint32_t m_pushBytes = 0;
    VkShaderModule m_module = VK_NULL_HANDLE;
    VkDescriptorSetLayout m_setLayout = VK_NULL_HANDLE;
    VkPipelineLayout m_pipelineLayout = VK_NULL_HANDLE;
    VkPipeline m_pipeline = VK_NULL_HANDLE;
    VkDescriptorPool m_pool = VK_NULL_HANDLE;
    VkDescriptorSet m_set = VK_NULL_HANDLE;
};

// A barrier that makes compute-shader writes visible to later compute-shader reads and
// writes (successive accumulation passes) and to transfers (readback).
void computeToComputeBarrier(VkCommandBuffer cmd);

}  // namespace penumbra::gpu
