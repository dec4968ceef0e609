// The micro-benchmarks' shared harness (see bench_harness.h).
#include "bench_harness.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "gpu/compute_pipeline.h"
#include "gpu/vk_check.h"

namespace penumbra::bench {

using gpu::vkCheck;

std::vector<uint32_t> readSpirv(const std::string& path, const std::string& target) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw std::runtime_error("cannot read " + path + " (build the " + target + " target)");
    std::vector<uint32_t> words(size_t(in.tellg()) / 4);
    in.seekg(0);
    in.read(reinterpret_cast<char*>(words.data()), std::streamsize(words.size() * 4));
    return words;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    double a = 0, b = 0, c = 0;
    in >> a >> b >> c;
    char text[64];
    std::snprintf(text, sizeof text, "%.2f, %.2f, %.2f", a, b, c);
    return text;
}

BenchKernel::BenchKernel(const gpu::Context& context, const std::vector<uint32_t>& spirv,
                         const std::vector<BenchBinding>& bindings, const void* push, uint32_t pushBytes,
                         uint32_t groups, const std::vector<uint32_t>& specialization)
    : m_context(context),
      m_push(static_cast<const uint8_t*>(push), static_cast<const uint8_t*>(push) + pushBytes),
      m_groups(groups) {
    VkDevice device = context.device();
    // The pipeline as the renderer's kernels make theirs (gpu/compute_pipeline.h); the
    // descriptor set is the harness's own, for bindings Kernel does not offer (sparse binding
    // numbers, sampled images, texel views made by the caller).
    std::vector<VkDescriptorSetLayoutBinding> layoutBindings;
    std::vector<VkDescriptorPoolSize> sizes;
    for (const BenchBinding& b : bindings) {
        layoutBindings.push_back({b.binding, b.type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
        sizes.push_back({b.type, 1});
    }
    m_pipeline = gpu::createComputePipeline(device, spirv, layoutBindings, pushBytes, specialization);

    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = uint32_t(sizes.size());
    poolInfo.pPoolSizes = sizes.data();
    vkCheck(vkCreateDescriptorPool(device, &poolInfo, nullptr, &m_pool), "create descriptor pool");
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = m_pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &m_pipeline.setLayout;
    vkCheck(vkAllocateDescriptorSets(device, &alloc, &m_set), "allocate descriptor set");

    // Pointers into these must stay valid until vkUpdateDescriptorSets: sized up front.
    std::vector<VkDescriptorBufferInfo> bufferInfos(bindings.size());
    std::vector<VkWriteDescriptorSet> writes(bindings.size(), {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET});
    for (size_t i = 0; i < bindings.size(); ++i) {
        const BenchBinding& b = bindings[i];
        VkWriteDescriptorSet& w = writes[i];
        w.dstSet = m_set;
        w.dstBinding = b.binding;
        w.descriptorCount = 1;
        w.descriptorType = b.type;
        if (b.type == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER || b.type == VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER) {
            w.pTexelBufferView = &b.texelView;
        } else if (b.type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER) {
            w.pImageInfo = &b.image;
        } else {
            bufferInfos[i] = {b.buffer, 0, VK_WHOLE_SIZE};
            w.pBufferInfo = &bufferInfos[i];
        }
    }
    vkUpdateDescriptorSets(device, uint32_t(writes.size()), writes.data(), 0, nullptr);
}

BenchKernel::~BenchKernel() {
    VkDevice device = m_context.device();
    vkDestroyDescriptorPool(device, m_pool, nullptr);
    gpu::destroyComputePipeline(device, m_pipeline);
}

double BenchKernel::run() const {
    auto start = std::chrono::steady_clock::now();
    m_context.submitAndWait([&](VkCommandBuffer cmd) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_pipeline.pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_pipeline.layout, 0, 1, &m_set, 0, nullptr);
        if (!m_push.empty())
            vkCmdPushConstants(cmd, m_pipeline.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, uint32_t(m_push.size()),
                               m_push.data());
        vkCmdDispatch(cmd, m_groups, 1, 1);
    });
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace penumbra::bench
