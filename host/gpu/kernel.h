// One compute pipeline with its descriptor set: the embedded shader, the descriptor
// types of bindings 0..n-1 of set 0, an optional push-constant block, and optional
// specialization constants (constant_id i = specialization[i]). The pipeline (where the
// driver compiles the shader) can be shared between kernels; see gpu/kernel_cache.h.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/shader_objects.h"

namespace penumbra::gpu {

// The immutable, costly part of a kernel: layouts and either a shader module with a compute
// pipeline or, on devices where kernels are shader objects (gpu/shader_objects.h), a shader
// object. Holds no buffers, so any number of Kernels may share one.
class Pipeline {
public:
    Pipeline(const Context& context, std::string_view shaderName, std::vector<VkDescriptorType> bindings,
             uint32_t pushConstantBytes = 0, std::vector<uint32_t> specialization = {});
    ~Pipeline();
    Pipeline(const Pipeline&) = delete;
    Pipeline& operator=(const Pipeline&) = delete;

    const std::string& name() const { return m_name; }
    const std::vector<VkDescriptorType>& bindings() const { return m_bindings; }
    uint32_t pushBytes() const { return m_pushBytes; }
    VkDescriptorSetLayout setLayout() const { return m_setLayout; }
    VkPipelineLayout layout() const { return m_pipelineLayout; }
    VkPipeline handle() const { return m_pipeline; }  // null for a shader object
    VkShaderEXT shader() const { return m_shader; }   // null for a pipeline
    // For a shader object: whether its binary came from disk (gpu/kernel_binaries.h).
    bool fromDisk() const { return m_shader && m_source == ShaderObjectSource::FromDisk; }

private:
    void destroy();

    const Context& m_context;
    std::string m_name;
    std::vector<VkDescriptorType> m_bindings;
    uint32_t m_pushBytes = 0;
    VkShaderModule m_module = VK_NULL_HANDLE;
    VkDescriptorSetLayout m_setLayout = VK_NULL_HANDLE;
    VkPipelineLayout m_pipelineLayout = VK_NULL_HANDLE;
    VkPipeline m_pipeline = VK_NULL_HANDLE;
    VkShaderEXT m_shader = VK_NULL_HANDLE;
    ShaderObjectSource m_source = ShaderObjectSource::Compiled;
};

class Kernel {
public:
    // Creates its own pipeline.
    Kernel(const Context& context, std::string_view shaderName, std::vector<VkDescriptorType> bindings,
           uint32_t pushConstantBytes = 0, std::vector<uint32_t> specialization = {});
    // Shares `pipeline` (e.g. from a KernelCache); only the descriptor set is its own.
    Kernel(const Context& context, std::shared_ptr<const Pipeline> pipeline);
    ~Kernel();
    Kernel(const Kernel&) = delete;
    Kernel& operator=(const Kernel&) = delete;

    // Points `binding` at the whole of `buffer` (kept by handle: the buffer must outlive use).
    // A texel-buffer binding (VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER) gets a view of the
    // buffer as RGBA32UI texels, owned by this kernel; such a buffer needs
    // VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT.
    void bind(uint32_t binding, const Buffer& buffer);

    // Records a dispatch of `groups` workgroups; `push` must hold pushConstantBytes bytes.
    void record(VkCommandBuffer cmd, uint32_t groupsX, uint32_t groupsY = 1, uint32_t groupsZ = 1,
                const void* push = nullptr) const;
    // Dispatches once and waits for the result.
    void run(uint32_t groupsX, uint32_t groupsY = 1, uint32_t groupsZ = 1, const void* push = nullptr) const;

    const Pipeline& pipeline() const { return *m_pipeline; }

private:
    const Context& m_context;
    std::shared_ptr<const Pipeline> m_pipeline;
    VkDescriptorPool m_pool = VK_NULL_HANDLE;
    VkDescriptorSet m_set = VK_NULL_HANDLE;
    std::vector<VkBufferView> m_views;  // per binding, VK_NULL_HANDLE unless a texel buffer
};

// A barrier that makes compute-shader writes visible to later compute-shader reads and
// writes (successive accumulation passes) and to transfers (readback).
void computeToComputeBarrier(VkCommandBuffer cmd);

// Fills `size` bytes of `buffer` from `offset` with copies of `value` between dispatches:
// after every earlier compute-shader access to them, before every later one (the tile
// queue's counter, render/tile_queue.h).
void fillBetweenDispatches(VkCommandBuffer cmd, const Buffer& buffer, VkDeviceSize offset, VkDeviceSize size,
                           uint32_t value);

}  // namespace penumbra::gpu
