// Device time of recorded stretches of commands, from timestamp queries: what
// Renderer::renderAll sizes its submissions by, since wall time also holds the fixed cost
// of each submission (on lavapipe on a loaded machine, tens of milliseconds of thread
// hand-offs) that does not grow with the work. One submission may time several stretches
// back to back (the bands it holds): a timestamp before the first and one after each.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "gpu/context.h"

namespace penumbra::gpu {

class GpuTimer {
public:
    // Up to `maxIntervals` stretches per submission.
    explicit GpuTimer(const Context& context, uint32_t maxIntervals = 1);
    ~GpuTimer();
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    // False when the queue has no timestamps; then seconds() gives negative times.
    bool supported() const { return m_pool != VK_NULL_HANDLE; }
    // Record before the first stretch of `intervals` (at most the constructor's maxIntervals).
    void start(VkCommandBuffer cmd, uint32_t intervals = 1) const;
    // Record after stretch `interval` (0, 1, ... in order): it ends there and the next begins.
    void stop(VkCommandBuffer cmd, uint32_t interval = 0) const;
    // After the submission has completed: the seconds of each of the `intervals` stretches,
    // or -1 for each when there are no timestamps.
    std::vector<double> seconds(uint32_t intervals) const;

private:
    const Context& m_context;
    uint32_t m_maxIntervals;
    VkQueryPool m_pool = VK_NULL_HANDLE;
    uint64_t m_mask = 0;  // the queue's valid timestamp bits
};

}  // namespace penumbra::gpu
