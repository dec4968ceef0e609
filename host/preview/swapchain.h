// The window's swapchain (RAII): an 8-bit RGBA format the preview can blit into, rebuilt
// on resize or when presentation reports it out of date, with one "rendered" semaphore per
// image for presentation to wait on. Nothing here records commands: the loop does.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.h"

namespace penumbra::preview {

class Swapchain {
public:
    // `framebuffer` is the window's size in pixels; a zero size (minimised) creates no
    // swapchain until recreate() is given a real one. The context must own a surface.
    Swapchain(const gpu::Context& context, VkExtent2D framebuffer);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    // Rebuilds for `framebuffer` (waits until the device is idle; the old swapchain is
    // handed to the new one, as the spec allows, then destroyed).
    void recreate(VkExtent2D framebuffer);

    // The next image to draw into, `ready` being signalled once it may be written;
    // nullopt when there is no swapchain or it is out of date (recreate it).
    std::optional<uint32_t> acquire(VkSemaphore ready);
    // Queues image `index` for presentation once renderedSemaphore(index) is signalled.
    // False when the swapchain is out of date or suboptimal (recreate it).
    bool present(uint32_t index);

    bool valid() const { return m_swapchain != VK_NULL_HANDLE; }
    VkImage image(uint32_t index) const { return m_images[index]; }
    VkSemaphore renderedSemaphore(uint32_t index) const { return m_rendered[index]; }
    VkFormat format() const { return m_format; }
    // True for *_SRGB formats: the blit into them encodes, so its source must be sRGB too.
    bool isSrgb() const;
    VkExtent2D extent() const { return m_extent; }

private:
    void create(VkExtent2D framebuffer);
    void destroy();

    const gpu::Context& m_context;
    VkSwapchainKHR m_swapchain = VK_NULL_HANDLE;
    std::vector<VkImage> m_images;         // owned by the swapchain
    std::vector<VkSemaphore> m_rendered;   // one per image
    VkFormat m_format = VK_FORMAT_UNDEFINED;
    VkExtent2D m_extent{0, 0};
};

}  // namespace penumbra::preview
