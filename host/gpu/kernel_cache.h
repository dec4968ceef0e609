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
    // How many pipelines stay held. Small scenes compile their shapes into the kernel, so
    // a batch that sweeps a small scene's geometry makes a pipeline per job; unbounded,
    // the compiled code of every job would stay in memory. Past the limit the least
    // recently requested pipeline is dropped (Kernels using it keep it alive); a batch
    // alternating between a few integrators or scenes keeps all of its pipelines.
    static constexpr size_t kMaxPipelines = 16;

    explicit KernelCache(const Context& context, size_t maxPipelines = kMaxPipelines)
        : m_context(context), m_maxPipelines(maxPipelines == 0 ? 1 : maxPipelines) {}
    KernelCache(const KernelCache&) = delete;
    KernelCache& operator=(const KernelCache&) = delete;

    // A new Kernel (its own descriptor set, nothing bound) whose pipeline is created on the
    // first request with these arguments and shared by every later one. Kernels keep their
    // pipeline alive, so they may outlive the cache (never the Context).
    std::unique_ptr<Kernel> kernel(std::string_view shaderName, const std::vector<VkDescriptorType>& bindings,
                                   uint32_t pushConstantBytes = 0, const std::vector<uint32_t>& specialization = {});

    size_t pipelinesCreated() const { return m_created; }
    size_t pipelinesReused() const { return m_reused; }
    size_t pipelinesHeld() const { return m_pipelines.size(); }

private:
    using Key = std::tuple<std::string, std::vector<VkDescriptorType>, uint32_t, std::vector<uint32_t>>;
    struct Entry {
        std::shared_ptr<const Pipeline> pipeline;
        uint64_t lastUse = 0;  // m_requests when last requested
    };
    const Context& m_context;
    size_t m_maxPipelines;
    std::map<Key, Entry> m_pipelines;
    size_t m_created = 0, m_reused = 0;
    uint64_t m_requests = 0;
};

}  // namespace penumbra::gpu
