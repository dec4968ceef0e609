// Compute pipeline creation from SPIR-V (see compute_pipeline.h), written once for the
// renderer's kernels and the micro-benchmarks.
#include "gpu/compute_pipeline.h"

#include "core/phases.h"
#include "gpu/spirv_specialization.h"
#include "gpu/vk_check.h"

namespace penumbra::gpu {

ComputePipelineObjects createComputeLayouts(VkDevice device, const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                                            uint32_t pushConstantBytes, const std::string& what) {
    ComputePipelineObjects made;
    try {
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
    } catch (...) {
        destroyComputePipeline(device, made);
        throw;
    }
    return made;
}

ComputePipelineObjects createComputePipeline(VkDevice device, std::span<const uint32_t> spirv,
                                             const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                                             uint32_t pushConstantBytes, const std::vector<uint32_t>& specialization,
                                             const std::string& what) {
    ComputePipelineObjects made = createComputeLayouts(device, bindings, pushConstantBytes, what);
    try {
        // The constants are applied before the driver sees the module (spirv_specialization.h),
        // so the pipeline gets none of its own.
        std::vector<uint32_t> specialized;
        if (!specialization.empty()) {
            Phase phase("specialize_spirv");
            specialized = specializeSpirv(spirv, specialization);
            spirv = specialized;
        }
        VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = spirv.size_bytes();
        moduleInfo.pCode = spirv.data();
        vkCheck(vkCreateShaderModule(device, &moduleInfo, nullptr, &made.module),
                ("create shader module" + what).c_str());

        VkComputePipelineCreateInfo pipelineInfo{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        pipelineInfo.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        pipelineInfo.stage.module = made.module;
        pipelineInfo.stage.pName = "main";
        pipelineInfo.layout = made.layout;
        Phase phase("create_pipeline");  // on lavapipe: SPIR-V to NIR, and NIR's passes
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
