// Compute pipeline creation from SPIR-V (see compute_pipeline.h), written once for the
// renderer's kernels and the micro-benchmarks.
#include "gpu/compute_pipeline.h"

#include "gpu/vk_check.h"

namespace penumbra::gpu {

ComputePipelineObjects createComputePipeline(VkDevice device, std::span<const uint32_t> spirv,
                                             const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                                             uint32_t pushConstantBytes, const std::vector<uint32_t>& specialization,
                                             const std::string& what) {
    ComputePipelineObjects made;
    try {
        VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = spirv.size_bytes();
        moduleInfo.pCode = spirv.data();
        vkCheck(vkCreateShaderModule(device, &moduleInfo, nullptr, &made.module),
                ("create shader module" + what).c_str());

        VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        setInfo.bindingCount = uint32_t(bindings.size());
        setInfo.pBindings = bindings.data();
        vkCheck(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &made.setLayout),
                ("create descriptor set layout" + what).c_str());

        VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes};
        VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        layoutInfo.setLayoutCount = 1;
        layoutInfo.pSetLayouts = &made.setLayout;
        layoutInfo.pushConstantRangeCount = pushConstantBytes ? 1 : 0;
        layoutInfo.pPushConstantRanges = &range;
        vkCheck(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &made.layout),
                ("create pipeline layout" + what).c_str());

        std::vector<VkSpecializationMapEntry> entries;
        for (uint32_t i = 0; i < specialization.size(); ++i)
            entries.push_back({i, uint32_t(i * sizeof(uint32_t)), sizeof(uint32_t)});
        VkSpecializationInfo specInfo{uint32_t(entries.size()), entries.data(),
                                      specialization.size() * sizeof(uint32_t), specialization.data()};
        VkComputePipelineCreateInfo pipelineInfo{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        pipelineInfo.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        pipelineInfo.stage.module = made.module;
        pipelineInfo.stage.pName = "main";
        pipelineInfo.stage.pSpecializationInfo = entries.empty() ? nullptr : &specInfo;
        pipelineInfo.layout = made.layout;
        vkCheck(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipelineInfo, nullptr, &made.pipeline),
                ("create compute pipeline" + what).c_str());
    } catch (...) {
        destroyComputePipeline(device, made);
        throw;
    }
    return made;
}

void destroyComputePipeline(VkDevice device, ComputePipelineObjects& objects) {
    if (objects.pipeline) vkDestroyPipeline(device, objects.pipeline, nullptr);
    if (objects.layout) vkDestroyPipelineLayout(device, objects.layout, nullptr);
    if (objects.setLayout) vkDestroyDescriptorSetLayout(device, objects.setLayout, nullptr);
    if (objects.module) vkDestroyShaderModule(device, objects.module, nullptr);
    objects = {};
}

}  // namespace penumbra::gpu
