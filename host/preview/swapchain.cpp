// Swapchain creation and recreation (see swapchain.h).
#ifdef PENUMBRA_HAVE_GLFW
#include "preview/swapchain.h"

#include <algorithm>

#include "gpu/vk_check.h"

namespace penumbra::preview {
namespace {

using gpu::vkCheck;

// 8-bit RGBA formats in order of preference: UNORM first, since the tone map already
// encodes sRGB; an *_SRGB swapchain works too (the blit source is then sRGB as well).
constexpr VkFormat kFormats[] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_A8B8G8R8_UNORM_PACK32,
                                 VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_R8G8B8A8_SRGB, VK_FORMAT_A8B8G8R8_SRGB_PACK32};

VkSurfaceFormatKHR chooseFormat(const gpu::Context& context) {
    uint32_t count = 0;
    vkCheck(vkGetPhysicalDeviceSurfaceFormatsKHR(context.physicalDevice(), context.surface(), &count, nullptr),
            "query the window's surface formats");
    std::vector<VkSurfaceFormatKHR> formats(count);
    vkCheck(vkGetPhysicalDeviceSurfaceFormatsKHR(context.physicalDevice(), context.surface(), &count, formats.data()),
            "query the window's surface formats");
    for (VkFormat wanted : kFormats)
        for (const VkSurfaceFormatKHR& f : formats) {
            if (f.format != wanted || f.colorSpace != VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) continue;
            VkFormatProperties props;
            vkGetPhysicalDeviceFormatProperties(context.physicalDevice(), f.format, &props);
            if (props.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_DST_BIT) return f;
        }
    throw gpu::GpuError("failed to find a swapchain format for the window (no 8-bit RGBA format that can be blitted to)");
}

VkPresentModeKHR choosePresentMode(const gpu::Context& context) {
    uint32_t count = 0;
    vkCheck(vkGetPhysicalDeviceSurfacePresentModesKHR(context.physicalDevice(), context.surface(), &count, nullptr),
            "query the window's present modes");
    std::vector<VkPresentModeKHR> modes(count);
    vkCheck(vkGetPhysicalDeviceSurfacePresentModesKHR(context.physicalDevice(), context.surface(), &count, modes.data()),
            "query the window's present modes");
    // Progressive rendering should never wait for a vertical blank: mailbox, then
    // immediate, then FIFO (always available).
    for (VkPresentModeKHR wanted : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
        if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) return wanted;
    return VK_PRESENT_MODE_FIFO_KHR;
}

}  // namespace

Swapchain::Swapchain(const gpu::Context& context, VkExtent2D framebuffer) : m_context(context) {
    if (context.surface() == VK_NULL_HANDLE) throw gpu::GpuError("failed to create a swapchain (no window surface)");
    create(framebuffer);
}

Swapchain::~Swapchain() {
    if (m_context.device()) vkDeviceWaitIdle(m_context.device());
    destroy();
}

bool Swapchain::isSrgb() const {
    return m_format == VK_FORMAT_B8G8R8A8_SRGB || m_format == VK_FORMAT_R8G8B8A8_SRGB ||
           m_format == VK_FORMAT_A8B8G8R8_SRGB_PACK32;
}

void Swapchain::recreate(VkExtent2D framebuffer) {
    vkCheck(vkDeviceWaitIdle(m_context.device()), "wait for the GPU before resizing the window's images");
    create(framebuffer);
}

void Swapchain::create(VkExtent2D framebuffer) {
    VkDevice device = m_context.device();
    // The old swapchain goes once the new one exists (or on any way out of here).
    struct Retired {
        VkDevice device;
        VkSwapchainKHR swapchain;
        ~Retired() {
            if (swapchain) vkDestroySwapchainKHR(device, swapchain, nullptr);
        }
    } retired{device, m_swapchain};
    for (VkSemaphore s : m_rendered) vkDestroySemaphore(device, s, nullptr);
    m_rendered.clear();
    m_images.clear();
    m_swapchain = VK_NULL_HANDLE;
    m_extent = {0, 0};

    VkSurfaceCapabilitiesKHR caps;
    VkResult capsResult = vkGetPhysicalDeviceSurfaceCapabilitiesKHR(m_context.physicalDevice(), m_context.surface(), &caps);
    vkCheck(capsResult, "query the window's surface capabilities");
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == UINT32_MAX) {
        extent.width = std::clamp(framebuffer.width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(framebuffer.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (extent.width == 0 || extent.height == 0 || framebuffer.width == 0 || framebuffer.height == 0) {
        return;  // minimised: nothing to present to until the window has a size again
    }
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        throw gpu::GpuError("failed to create a swapchain (the window's images cannot be transfer destinations)");
    VkSurfaceFormatKHR format = chooseFormat(m_context);

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = m_context.surface();
    info.minImageCount = caps.minImageCount + 1;
    if (caps.maxImageCount > 0) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
    info.imageFormat = format.format;
    info.imageColorSpace = format.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;  // cleared and blitted into, never rendered to
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    if (!(caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR))
        for (uint32_t bit = 1; bit != 0 && bit <= caps.supportedCompositeAlpha; bit <<= 1)
            if (caps.supportedCompositeAlpha & bit) {
                info.compositeAlpha = VkCompositeAlphaFlagBitsKHR(bit);
                break;
            }
    info.presentMode = choosePresentMode(m_context);
    info.clipped = VK_TRUE;
    info.oldSwapchain = retired.swapchain;
    vkCheck(vkCreateSwapchainKHR(device, &info, nullptr, &m_swapchain), "create the window's swapchain");
    m_format = format.format;
    m_extent = extent;

    uint32_t count = 0;
    vkCheck(vkGetSwapchainImagesKHR(device, m_swapchain, &count, nullptr), "get the swapchain images");
    m_images.resize(count);
    vkCheck(vkGetSwapchainImagesKHR(device, m_swapchain, &count, m_images.data()), "get the swapchain images");
    m_images.resize(count);
    for (uint32_t i = 0; i < count; ++i) {
        VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore semaphore = VK_NULL_HANDLE;
        vkCheck(vkCreateSemaphore(device, &semaphoreInfo, nullptr, &semaphore), "create a presentation semaphore");
        m_rendered.push_back(semaphore);
    }
}

void Swapchain::destroy() {
    VkDevice device = m_context.device();
    for (VkSemaphore s : m_rendered) vkDestroySemaphore(device, s, nullptr);
    m_rendered.clear();
    m_images.clear();
    if (m_swapchain) vkDestroySwapchainKHR(device, m_swapchain, nullptr);
    m_swapchain = VK_NULL_HANDLE;
}

std::optional<uint32_t> Swapchain::acquire(VkSemaphore ready) {
    if (!m_swapchain) return std::nullopt;
    uint32_t index = 0;
    VkResult result = vkAcquireNextImageKHR(m_context.device(), m_swapchain, UINT64_MAX, ready, VK_NULL_HANDLE, &index);
    if (result == VK_ERROR_OUT_OF_DATE_KHR) return std::nullopt;
    if (result != VK_SUBOPTIMAL_KHR) vkCheck(result, "acquire a swapchain image");
    return index;
}

bool Swapchain::present(uint32_t index) {
    VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    info.waitSemaphoreCount = 1;
    info.pWaitSemaphores = &m_rendered[index];
    info.swapchainCount = 1;
    info.pSwapchains = &m_swapchain;
    info.pImageIndices = &index;
    VkResult result = vkQueuePresentKHR(m_context.queue(), &info);
    if (result == VK_ERROR_OUT_OF_DATE_KHR || result == VK_SUBOPTIMAL_KHR) return false;
    vkCheck(result, "present to the window");
    return true;
}

}  // namespace penumbra::preview
#endif  // PENUMBRA_HAVE_GLFW
