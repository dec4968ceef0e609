// Compute pipeline creation, descriptor sets and updates, and dispatch recording.
#include "gpu/kernel.h"

#include "gpu/compute_pipeline.h"
#include "gpu/shader_objects.h"
#include "gpu/shaders.h"
#include "gpu/vk_check.h"

namespace penumbra::gpu {

Pipeline::Pipeline(const Context& context, std::string_view shaderName, std::vector<VkDescriptorType> bindings,
                   uint32_t pushConstantBytes, std::vector<uint32_t> specialization)
    : m_context(context), m_name(shaderName), m_bindings(std::move(bindings)), m_pushBytes(pushConstantBytes) {
    std::vector<VkDescriptorSetLayoutBinding> layoutBindings;
    for (uint32_t i = 0; i < m_bindings.size(); ++i)
        layoutBindings.push_back({i, m_bindings[i], 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    const std::string what = " for shader " + m_name;
    if (!context.shaderObjects()) {
        ComputePipelineObjects made = createComputePipeline(context.device(), shaderCode(shaderName), layoutBindings,
                                                            m_pushBytes, specialization, what);
        m_module = made.module;
        m_setLayout = made.setLayout;
        m_pipelineLayout = made.layout;
        m_pipeline = made.pipeline;
        return;
    }
    // A shader object instead of a pipeline (gpu/shader_objects.h); the layouts serve
    // binding its descriptor set and push constants all the same.
    ComputePipelineObjects made = createComputeLayouts(context.device(), layoutBindings, m_pushBytes, what);
    m_setLayout = made.setLayout;
    m_pipelineLayout = made.layout;
    try {
        m_shader = createComputeShaderObject(context, shaderCode(shaderName), specialization, m_setLayout, m_pushBytes,
                                             what, &m_source);
    } catch (...) {
        destroy();
        throw;
    }
}

Pipeline::~Pipeline() { destroy(); }

void Pipeline::destroy() {
    if (m_shader) m_context.shaderObjects()->destroy(m_context.device(), m_shader, nullptr);
    m_shader = VK_NULL_HANDLE;
    ComputePipelineObjects objects{m_module, m_setLayout, m_pipelineLayout, m_pipeline};
    destroyComputePipeline(m_context.device(), objects);
    m_pipeline = VK_NULL_HANDLE;
    m_pipelineLayout = VK_NULL_HANDLE;
    m_setLayout = VK_NULL_HANDLE;
    m_module = VK_NULL_HANDLE;
}

Kernel::Kernel(const Context& context, std::string_view shaderName, std::vector<VkDescriptorType> bindings,
               uint32_t pushConstantBytes, std::vector<uint32_t> specialization)
    : Kernel(context, std::make_shared<const Pipeline>(context, shaderName, std::move(bindings), pushConstantBytes,
                                                       std::move(specialization))) {}

Kernel::Kernel(const Context& context, std::shared_ptr<const Pipeline> pipeline)
    : m_context(context), m_pipeline(std::move(pipeline)) {
    if (m_pipeline->bindings().empty()) return;
    std::string what = " for shader " + m_pipeline->name();
    VkDevice device = context.device();
    std::vector<VkDescriptorPoolSize> sizes;
    for (VkDescriptorType type : m_pipeline->bindings()) sizes.push_back({type, 1});
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = uint32_t(sizes.size());
    poolInfo.pPoolSizes = sizes.data();
    vkCheck(vkCreateDescriptorPool(device, &poolInfo, nullptr, &m_pool), ("create descriptor pool" + what).c_str());
    VkDescriptorSetLayout setLayout = m_pipeline->setLayout();
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = m_pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &setLayout;
    VkResult result = vkAllocateDescriptorSets(device, &alloc, &m_set);
    if (result != VK_SUCCESS) {
        vkDestroyDescriptorPool(device, m_pool, nullptr);
        m_pool = VK_NULL_HANDLE;
        vkCheck(result, ("allocate descriptor set" + what).c_str());
    }
}

Kernel::~Kernel() {
    for (VkBufferView view : m_views)
        if (view) vkDestroyBufferView(m_context.device(), view, nullptr);
    if (m_pool) vkDestroyDescriptorPool(m_context.device(), m_pool, nullptr);  // frees m_set too
}

void Kernel::bind(uint32_t binding, const Buffer& buffer) {
    const auto& bindings = m_pipeline->bindings();
    if (binding >= bindings.size()) throw GpuError("binding out of range for shader " + m_pipeline->name());
    VkDescriptorBufferInfo info{buffer.handle(), 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = m_set;
    write.dstBinding = binding;
    write.descriptorCount = 1;
    write.descriptorType = bindings[binding];
    write.pBufferInfo = &info;
    if (bindings[binding] == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER) {
        // Texels of 16 bytes; buffers are at least 16 bytes, so the view is never empty.
        VkDevice device = m_context.device();
        m_views.resize(bindings.size(), VK_NULL_HANDLE);
        VkBufferViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
        viewInfo.buffer = buffer.handle();
        viewInfo.format = VK_FORMAT_R32G32B32A32_UINT;
        viewInfo.offset = 0;
        viewInfo.range = buffer.size() / 16 * 16;
        VkBufferView view = VK_NULL_HANDLE;
        vkCheck(vkCreateBufferView(device, &viewInfo, nullptr, &view),
                ("create texel buffer view for shader " + m_pipeline->name()).c_str());
        if (m_views[binding]) vkDestroyBufferView(device, m_views[binding], nullptr);
        m_views[binding] = view;
        write.pBufferInfo = nullptr;
        write.pTexelBufferView = &m_views[binding];
    }
    vkUpdateDescriptorSets(m_context.device(), 1, &write, 0, nullptr);
}

void Kernel::record(VkCommandBuffer cmd, uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ,
                    const void* push) const {
    const Pipeline& p = *m_pipeline;
    if (p.shader()) {
        const VkShaderStageFlagBits stage = VK_SHADER_STAGE_COMPUTE_BIT;
        const VkShaderEXT shader = p.shader();
        m_context.shaderObjects()->bind(cmd, 1, &stage, &shader);
    } else {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.handle());
    }
    if (m_set) vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, 1, &m_set, 0, nullptr);
    if (p.pushBytes() && push)
        vkCmdPushConstants(cmd, p.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, p.pushBytes(), push);
    vkCmdDispatch(cmd, groupsX, groupsY, groupsZ);
}

void Kernel::run(uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ, const void* push) const {
    m_context.submitAndWait([&](VkCommandBuffer cmd) {
        record(cmd, groupsX, groupsY, groupsZ, push);
        computeToComputeBarrier(cmd);
    });
}

void computeToComputeBarrier(VkCommandBuffer cmd) {
    // Shader writes of one dispatch -> shader reads/writes of the next, and host/transfer reads.
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                            VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                         0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void fillBetweenDispatches(VkCommandBuffer cmd, const Buffer& buffer, VkDeviceSize offset, VkDeviceSize size,
                           uint32_t value) {
    const VkAccessFlags shaderAccess = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
    VkMemoryBarrier before{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    before.srcAccessMask = shaderAccess;
    before.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &before, 0,
                         nullptr, 0, nullptr);
    vkCmdFillBuffer(cmd, buffer.handle(), offset, size, value);
    VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    after.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    after.dstAccessMask = shaderAccess;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &after, 0,
                         nullptr, 0, nullptr);
}

}  // namespace penumbra::gpu
