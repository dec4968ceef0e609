// Device time of a recorded stretch of commands, from two timestamp queries: what
// Renderer::renderAll sizes its submissions by, since wall time also holds the fixed cost
// of each submission (on lavapipe on a loaded machine, tens of milliseconds of thread
// hand-offs) that does not grow with the work.
#pragma once

#include <vulkan/vulkan.h>

#include "gpu/context.h"

namespace penumbra::gpu {

class GpuTimer {
public:
    explicit GpuTimer(const Context& context);
    ~GpuTimer();
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    // False when the queue has no timestamps; then seconds() is always negative.
    bool supported() const { return m_pool != VK_NULL_HANDLE; }
    // Record around the commands to time (start before, stop after them).
    void start(VkCommandBuffer cmd) const;
    void stop(VkCommandBuffer cmd) const;
    // After the submission has completed: the seconds between start and stop, or -1.
    double seconds() const;

private:
    const Context& m_context;
    VkQueryPool m_pool = VK_NULL_HANDLE;
    uint64_t m_mask = 0;  // the queue's valid timestamp bits
};

}  // namespace penumbra::gpu
