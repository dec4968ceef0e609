// Timestamp queries (see gpu_timer.h).
#include "gpu/gpu_timer.h"

#include <vector>

#include "gpu/vk_check.h"

namespace penumbra::gpu {

GpuTimer::GpuTimer(const Context& context) : m_context(context) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice(), &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice(), &count, families.data());
    const uint32_t bits = context.queueFamily() < count ? families[context.queueFamily()].timestampValidBits : 0;
    if (bits == 0 || context.limits().timestampPeriod <= 0.0f) return;
    m_mask = bits >= 64 ? ~uint64_t(0) : (uint64_t(1) << bits) - 1;
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2;
    if (vkCreateQueryPool(context.device(), &info, nullptr, &m_pool) != VK_SUCCESS) m_pool = VK_NULL_HANDLE;
}

GpuTimer::~GpuTimer() {
    if (m_pool) vkDestroyQueryPool(m_context.device(), m_pool, nullptr);
}

void GpuTimer::start(VkCommandBuffer cmd) const {
    if (!m_pool) return;
    vkCmdResetQueryPool(cmd, m_pool, 0, 2);
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, m_pool, 0);
}

void GpuTimer::stop(VkCommandBuffer cmd) const {
    if (m_pool) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m_pool, 1);
}

double GpuTimer::seconds() const {
    if (!m_pool) return -1.0;
    uint64_t stamps[2] = {0, 0};
    if (vkGetQueryPoolResults(m_context.device(), m_pool, 0, 2, sizeof stamps, stamps, sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) != VK_SUCCESS)
        return -1.0;
    const uint64_t ticks = ((stamps[1] & m_mask) - (stamps[0] & m_mask)) & m_mask;
    return double(ticks) * double(m_context.limits().timestampPeriod) * 1e-9;
}

}  // namespace penumbra::gpu
