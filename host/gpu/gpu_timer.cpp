// Timestamp queries (see gpu_timer.h).
#include "gpu/gpu_timer.h"

#include <stdexcept>

#include "gpu/vk_check.h"

namespace penumbra::gpu {

GpuTimer::GpuTimer(const Context& context, uint32_t maxIntervals) : m_context(context), m_maxIntervals(maxIntervals) {
    if (maxIntervals == 0) throw std::invalid_argument("GpuTimer: no intervals to time");
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice(), &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice(), &count, families.data());
    const uint32_t bits = context.queueFamily() < count ? families[context.queueFamily()].timestampValidBits : 0;
    if (bits == 0 || context.limits().timestampPeriod <= 0.0f) return;
    m_mask = bits >= 64 ? ~uint64_t(0) : (uint64_t(1) << bits) - 1;
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = maxIntervals + 1;
    if (vkCreateQueryPool(context.device(), &info, nullptr, &m_pool) != VK_SUCCESS) m_pool = VK_NULL_HANDLE;
}

GpuTimer::~GpuTimer() {
    if (m_pool) vkDestroyQueryPool(m_context.device(), m_pool, nullptr);
}

void GpuTimer::start(VkCommandBuffer cmd, uint32_t intervals) const {
    if (intervals == 0 || intervals > m_maxIntervals)
        throw std::logic_error("GpuTimer::start: more intervals than the timer holds");
    if (!m_pool) return;
    vkCmdResetQueryPool(cmd, m_pool, 0, intervals + 1);
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, m_pool, 0);
}

void GpuTimer::stop(VkCommandBuffer cmd, uint32_t interval) const {
    if (interval >= m_maxIntervals) throw std::logic_error("GpuTimer::stop: no such interval");
    if (m_pool) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m_pool, interval + 1);
}

std::vector<double> GpuTimer::seconds(uint32_t intervals) const {
    std::vector<double> out(intervals, -1.0);
    if (!m_pool || intervals == 0 || intervals > m_maxIntervals) return out;
    std::vector<uint64_t> stamps(intervals + 1, 0);
    if (vkGetQueryPoolResults(m_context.device(), m_pool, 0, intervals + 1, stamps.size() * sizeof(uint64_t),
                              stamps.data(), sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) != VK_SUCCESS)
        return out;
    for (uint32_t i = 0; i < intervals; ++i) {
        const uint64_t ticks = ((stamps[i + 1] & m_mask) - (stamps[i] & m_mask)) & m_mask;
        out[i] = double(ticks) * double(m_context.limits().timestampPeriod) * 1e-9;
    }
    return out;
}

}  // namespace penumbra::gpu
