// What every micro-benchmark program shares: reading a kernel's SPIR-V, one compute kernel
// with its descriptor set timed dispatch by dispatch (BenchKernel), medians and the
// machine's load average (the machine may be shared: every table prints it).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/compute_pipeline.h"
#include "gpu/context.h"

namespace penumbra::bench {

constexpr uint32_t kWorkgroup = 64;  // local_size_x of every micro-benchmark kernel

// The SPIR-V words of `path`; throws naming `target` (the CMake target that builds it).
std::vector<uint32_t> readSpirv(const std::string& path, const std::string& target);

double median(std::vector<double> v);

// "/proc/loadavg"'s three averages, "a, b, c".
std::string loadAverage();

// One descriptor of a kernel's set 0: a buffer, a texel-buffer view or a sampled image.
struct BenchBinding {
    uint32_t binding = 0;
    VkDescriptorType type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    VkBuffer buffer = VK_NULL_HANDLE;         // storage and uniform buffers (whole)
    VkBufferView texelView = VK_NULL_HANDLE;  // uniform and storage texel buffers
    VkDescriptorImageInfo image{};            // combined image samplers
};

// A compute pipeline from a SPIR-V file, its descriptor set (`bindings`), push constants
// and specialization constants (constant_id i = specialization[i]); run() times one
// dispatch of `groups` workgroups, submitted and waited for.
class BenchKernel {
public:
    BenchKernel(const gpu::Context& context, const std::vector<uint32_t>& spirv,
                const std::vector<BenchBinding>& bindings, const void* push, uint32_t pushBytes, uint32_t groups,
                const std::vector<uint32_t>& specialization = {});
    ~BenchKernel();
    BenchKernel(const BenchKernel&) = delete;
    BenchKernel& operator=(const BenchKernel&) = delete;

    double run() const;

private:
    const gpu::Context& m_context;
    std::vector<uint8_t> m_push;
    uint32_t m_groups;
    gpu::ComputePipelineObjects m_pipeline;
    VkDescriptorPool m_pool = VK_NULL_HANDLE;
    VkDescriptorSet m_set = VK_NULL_HANDLE;
};

}  // namespace penumbra::bench
