// Pipeline lookup and creation for KernelCache (see kernel_cache.h).
#include "gpu/kernel_cache.h"

namespace penumbra::gpu {

std::unique_ptr<Kernel> KernelCache::kernel(std::string_view shaderName, const std::vector<VkDescriptorType>& bindings,
                                            uint32_t pushConstantBytes, const std::vector<uint32_t>& specialization) {
    Key key{std::string(shaderName), bindings, pushConstantBytes, specialization};
    auto it = m_pipelines.find(key);
    if (it != m_pipelines.end()) {
        ++m_reused;
    } else {
        auto pipeline = std::make_shared<const Pipeline>(m_context, shaderName, bindings, pushConstantBytes, specialization);
        it = m_pipelines.emplace(std::move(key), std::move(pipeline)).first;
        ++m_created;
    }
    return std::make_unique<Kernel>(m_context, it->second);
}

}  // namespace penumbra::gpu
