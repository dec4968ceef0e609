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
        if (m_pipelines.size() >= m_maxPipelines) {
            // A linear scan: the cache holds at most kMaxPipelines entries, and each miss
            // costs a driver compilation, far more than the scan.
            auto oldest = m_pipelines.begin();
            for (auto e = m_pipelines.begin(); e != m_pipelines.end(); ++e)
                if (e->second.lastUse < oldest->second.lastUse) oldest = e;
            m_pipelines.erase(oldest);
        }
        it = m_pipelines.emplace(std::move(key), Entry{std::move(pipeline)}).first;
        ++m_created;
    }
    it->second.lastUse = ++m_requests;
    return std::make_unique<Kernel>(m_context, it->second.pipeline);
}

}  // namespace penumbra::gpu
