// Creation and upload of a sampled image (see sampled_image.h).
#include "gpu/sampled_image.h"

#include <string>

#include "gpu/buffer.h"
#include "gpu/vk_check.h"

namespace penumbra::gpu {

SampledImage::SampledImage(const Context& context, uint32_t width, uint32_t height, std::span<const uint16_t> halves,
                           std::string_view name)
    : m_context(context) {
    const uint32_t maxSide = context.limits().maxImageDimension2D;
    if (width > maxSide || height > maxSide)
        throw GpuError("the " + std::string(name) + " image needs " + std::to_string(width) + " x " +
                       std::to_string(height) + " texels, more than this device's maxImageDimension2D (" +
                       std::to_string(maxSide) + "); use fewer or smaller textures, or a device with a larger limit");
    if (halves.size() != size_t(width) * height * 4)
        throw GpuError("the " + std::string(name) + " texels are not W x H RGBA");
    VkDevice device = context.device();
    // The staging buffer first: it checks the size against maxMemoryAllocationSize.
    const VkDeviceSize bytes = halves.size_bytes();
    Buffer staging(context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, 0, name);
    staging.upload(halves.data(), bytes);
    try {
        VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        info.imageType = VK_IMAGE_TYPE_2D;
        info.format = VK_FORMAT_R16G16B16A16_SFLOAT;
        info.extent = {width, height, 1};
        info.mipLevels = 1;
        info.arrayLayers = 1;
        info.samples = VK_SAMPLE_COUNT_1_BIT;
        info.tiling = VK_IMAGE_TILING_OPTIMAL;
        info.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        vkCheck(vkCreateImage(device, &info, nullptr, &m_image), "create image");
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(device, m_image, &req);
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.allocationSize = req.size;
        alloc.memoryTypeIndex = context.findMemoryType(req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        vkCheck(vkAllocateMemory(device, &alloc, nullptr, &m_memory),
                ("allocate " + std::to_string(req.size >> 20) + " MiB of GPU memory for the " + std::string(name) +
                 " image")
                    .c_str());
        vkCheck(vkBindImageMemory(device, m_image, m_memory, 0), "bind image memory");

        context.submitAndWait([&](VkCommandBuffer cmd) {
            VkImageMemoryBarrier toCopy{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
            toCopy.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            toCopy.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
            toCopy.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            toCopy.srcQueueFamilyIndex = toCopy.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            toCopy.image = m_image;
            toCopy.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            // Nothing comes before: the image is new; the copy waits for the layout change.
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr,
                                 0, nullptr, 1, &toCopy);
            VkBufferImageCopy region{};
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.imageExtent = {width, height, 1};
            vkCmdCopyBufferToImage(cmd, staging.handle(), m_image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
            // The copy's writes -> the kernels' sampled reads.
            VkImageMemoryBarrier toRead = toCopy;
            toRead.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            toRead.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
            toRead.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            toRead.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0,
                                 nullptr, 0, nullptr, 1, &toRead);
        });

        VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        view.image = m_image;
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.format = info.format;
        view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCheck(vkCreateImageView(device, &view, nullptr, &m_view), "create image view");
        // Unnormalized coordinates (texels, not [0, 1]) require clamping addressing, one
        // level and an explicit LOD of 0 (Vulkan spec, VkSamplerCreateInfo); the kernels
        // wrap coordinates themselves.
        VkSamplerCreateInfo sampler{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
        sampler.magFilter = sampler.minFilter = VK_FILTER_LINEAR;
        sampler.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
        sampler.addressModeU = sampler.addressModeV = sampler.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        sampler.minLod = sampler.maxLod = 0.0f;
        sampler.unnormalizedCoordinates = VK_TRUE;
        vkCheck(vkCreateSampler(device, &sampler, nullptr, &m_sampler), "create sampler");
    } catch (...) {
        release();
        throw;
    }
}

SampledImage::~SampledImage() { release(); }

void SampledImage::release() noexcept {
    VkDevice device = m_context.device();
    if (m_sampler) vkDestroySampler(device, m_sampler, nullptr);
    if (m_view) vkDestroyImageView(device, m_view, nullptr);
    if (m_image) vkDestroyImage(device, m_image, nullptr);
    if (m_memory) vkFreeMemory(device, m_memory, nullptr);
    m_sampler = VK_NULL_HANDLE;
    m_view = VK_NULL_HANDLE;
    m_image = VK_NULL_HANDLE;
    m_memory = VK_NULL_HANDLE;
}

}  // namespace penumbra::gpu
