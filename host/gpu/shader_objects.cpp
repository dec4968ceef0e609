// Kernels as shader objects, with their binaries on disk (see shader_objects.h).
#include "gpu/shader_objects.h"

#include <cstdio>
#include <vector>

#include "core/phases.h"
#include "gpu/kernel_binaries.h"
#include "gpu/spirv_specialization.h"
#include "gpu/vk_check.h"

namespace penumbra::gpu {

bool kernelsAsShaderObjects(const DeviceInfo& info) { return info.driverName == "llvmpipe" && info.shaderObject; }

namespace {

// Everything a binary depends on, as text: the device (its name carries llvmpipe's SIMD
// width), the driver and its binary UUID and version, the push constants' size, the SPIR-V
// (whose declarations fix the descriptor layout) and the specialization constants.
std::string binaryKey(const DeviceInfo& info, std::span<const uint32_t> spirv, const std::vector<uint32_t>& values,
                      uint32_t pushConstantBytes) {
    std::string key = "penumbra kernel binary 1\n" + info.name + "\n" + info.driverName + "\n" + info.driverInfo + "\n";
    char hex[3];
    for (uint8_t byte : info.shaderBinaryUuid) {
        std::snprintf(hex, sizeof hex, "%02x", byte);
        key += hex;
    }
    key += "\n" + std::to_string(info.shaderBinaryVersion) + "\n" + std::to_string(pushConstantBytes) + "\n";
    char spirvHash[40];
    std::snprintf(spirvHash, sizeof spirvHash, "%016llx %zu\n",
                  static_cast<unsigned long long>(fnv1a64(spirv.data(), spirv.size_bytes())), spirv.size());
    key += spirvHash;
    for (uint32_t value : values) key += std::to_string(value) + " ";
    return key;
}

VkShaderCreateInfoEXT computeShaderInfo(VkDescriptorSetLayout* setLayout, VkPushConstantRange* range) {
    VkShaderCreateInfoEXT info{VK_STRUCTURE_TYPE_SHADER_CREATE_INFO_EXT};
    info.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.pName = "main";
    info.setLayoutCount = 1;
    info.pSetLayouts = setLayout;
    info.pushConstantRangeCount = range->size ? 1 : 0;
    info.pPushConstantRanges = range;
    return info;
}

}  // namespace

VkShaderEXT createComputeShaderObject(const Context& context, std::span<const uint32_t> spirv,
                                      const std::vector<uint32_t>& specialization, VkDescriptorSetLayout setLayout,
                                      uint32_t pushConstantBytes, const std::string& what, ShaderObjectSource* source) {
    const ShaderObjectFunctions* f = context.shaderObjects();
    if (!f) throw GpuError("shader objects are not enabled on this device" + what);
    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes};
    const KernelBinaries binaries(KernelBinaries::folderFromEnvironment());
    const std::string key = binaryKey(context.info(), spirv, specialization, pushConstantBytes);
    VkShaderEXT shader = VK_NULL_HANDLE;
    if (auto binary = binaries.load(key)) {
        Phase phase("shader_from_disk");
        VkShaderCreateInfoEXT info = computeShaderInfo(&setLayout, &range);
        info.codeType = VK_SHADER_CODE_TYPE_BINARY_EXT;
        info.codeSize = binary->size();
        info.pCode = binary->data();
        // A binary the driver refuses (another driver build, a damaged file) is compiled anew.
        if (f->create(context.device(), 1, &info, nullptr, &shader) == VK_SUCCESS && shader != VK_NULL_HANDLE) {
            if (source) *source = ShaderObjectSource::FromDisk;
            return shader;
        }
        shader = VK_NULL_HANDLE;
    }
    // Only a binary that is not on disk needs the constants applied (the key holds them).
    std::vector<uint32_t> specialized;
    if (!specialization.empty()) {
        Phase phase("specialize_spirv");
        specialized = specializeSpirv(spirv, specialization);
        spirv = specialized;
    }
    {
        Phase phase("create_shader");  // SPIR-V to NIR and NIR's passes, as for a pipeline
        VkShaderCreateInfoEXT info = computeShaderInfo(&setLayout, &range);
        info.codeType = VK_SHADER_CODE_TYPE_SPIRV_EXT;
        info.codeSize = spirv.size_bytes();
        info.pCode = spirv.data();
        vkCheck(f->create(context.device(), 1, &info, nullptr, &shader), ("create shader object" + what).c_str());
    }
    if (source) *source = ShaderObjectSource::Compiled;
    if (binaries.enabled()) {
        size_t size = 0;
        std::vector<uint8_t> binary;
        if (f->binaryData(context.device(), shader, &size, nullptr) == VK_SUCCESS && size > 0) {
            binary.resize(size);
            if (f->binaryData(context.device(), shader, &size, binary.data()) == VK_SUCCESS) {
                binary.resize(size);
                binaries.store(key, binary);
            }
        }
    }
    return shader;
}

}  // namespace penumbra::gpu
