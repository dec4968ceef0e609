// Compute pipelines kept for reuse: a process that renders many scenes (penumbra batch)
// creates each pipeline once, since creating it is where the driver compiles the shader
// (the costly part on lavapipe). A pipeline is keyed by all its specialization constants,
// so scenes share one when their kernel options agree (render/kernel_options.h; a small
// scene's shapes are among them: render/inline_geometry.h). Descriptor sets stay per Kernel.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "gpu/kernel.h"

namespace penumbra::gpu {

class KernelCache {
public:
    explicit KernelCache(const Context& context) : m_context(context) {}
    KernelCache(const KernelCache&) = delete;
    KernelCache& operator=(const KernelCache&) = delete;

    // A new Kernel (its own descriptor set, nothing bound) whose pipeline is created on the
    // first request with these arguments and shared by every later one. Kernels keep their
    // pipeline alive, so they may outlive the cache (never the Context).
    std::unique_ptr<Kernel> kernel(std::string_view shaderName, const std::vector<VkDescriptorType>& bindings,
                                   uint32_t pushConstantBytes = 0, const std::vector<uint32_t>& specialization = {});

    size_t pipelinesCreated() const { return m_created; }
    size_t pipelinesReused() const { return m_reused; }

private:
    using Key = std::tuple<std::string, std::vector<VkDescriptorType>, uint32_t, std::vector<uint32_t>>;
    const Context& m_context;
    std::map<Key, std::shared_ptr<const Pipeline>> m_pipelines;
    size_t m_created = 0, m_reused = 0;
};

}  // namespace penumbra::gpu
