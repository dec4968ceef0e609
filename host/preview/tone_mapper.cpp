// Tone map, display image and blit of the preview (see tone_mapper.h).
#ifdef PENUMBRA_HAVE_GLFW
#include "preview/tone_mapper.h"

#include <cmath>
#include <stdexcept>

#include "gpu/vk_check.h"
#include "shared/types.h"

namespace penumbra::preview {
namespace {

using gpu::vkCheck;

std::vector<VkDescriptorType> toneMapBindings() {
    return std::vector<VkDescriptorType>(TONEMAP_BINDING_COUNT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
}

}  // namespace

ToneMapper::ToneMapper(const gpu::Context& context, const gpu::Buffer& accumulation, const gpu::Buffer& compensation,
                       uint32_t width, uint32_t height, bool srgbImage)
    : m_context(context),
      m_width(width),
      m_height(height),
      m_srgb(srgbImage),
      m_pixels(context, VkDeviceSize(width) * height * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT),
      m_kernel(context, "preview/tonemap", toneMapBindings(), uint32_t(sizeof(gpu::ToneMapConstants))) {
    m_kernel.bind(TONEMAP_BINDING_ACCUM, accumulation);
    m_kernel.bind(TONEMAP_BINDING_PIXELS, m_pixels);
    m_kernel.bind(TONEMAP_BINDING_COMPENSATION, compensation);

    const VkFormat format = srgbImage ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
    VkFormatProperties props;
    vkGetPhysicalDeviceFormatProperties(context.physicalDevice(), format, &props);
    if (!(props.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_SRC_BIT))
        throw gpu::GpuError("failed to set up the preview: the device cannot blit from RGBA8 images");
    if (props.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT) m_filter = VK_FILTER_LINEAR;

    VkDevice device = context.device();
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {width, height, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    vkCheck(vkCreateImage(device, &info, nullptr, &m_image), "create the preview's display image");
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device, m_image, &req);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = context.findMemoryType(req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VkResult result = vkAllocateMemory(device, &alloc, nullptr, &m_memory);
    if (result != VK_SUCCESS) {
        vkDestroyImage(device, m_image, nullptr);
        vkCheck(result, "allocate memory for the preview's display image");
    }
    vkCheck(vkBindImageMemory(device, m_image, m_memory, 0), "bind the preview's display image memory");
}

ToneMapper::~ToneMapper() {
    VkDevice device = m_context.device();
    if (m_image) vkDestroyImage(device, m_image, nullptr);
    if (m_memory) vkFreeMemory(device, m_memory, nullptr);
}

void ToneMapper::record(VkCommandBuffer cmd, ToneLook look) const {
    gpu::ToneMapConstants constants{m_width, m_height, std::exp2(look.exposure), uint32_t(look.curve)};
    m_kernel.record(cmd, (m_width + 7) / 8, (m_height + 7) / 8, 1, &constants);
    recordShowPixels(cmd);
}

void ToneMapper::setPixels(const std::vector<uint32_t>& packed) {
    if (packed.size() != size_t(m_width) * m_height) throw std::logic_error("ToneMapper::setPixels: wrong pixel count");
    m_pixels.upload(packed.data(), packed.size() * sizeof(uint32_t));
}

void ToneMapper::recordShowPixels(VkCommandBuffer cmd) const {
    // The tone map's writes to the pixel buffer (or setPixels' upload, finished before
    // this submission) -> the copy's transfer reads.
    VkBufferMemoryBarrier pixelsReady{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
    pixelsReady.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    pixelsReady.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    pixelsReady.srcQueueFamilyIndex = pixelsReady.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    pixelsReady.buffer = m_pixels.handle();
    pixelsReady.size = VK_WHOLE_SIZE;
    // The last blit's reads of the display image -> this copy's writes (its old contents are discarded).
    VkImageMemoryBarrier toCopy{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    toCopy.srcAccessMask = 0;
    toCopy.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    toCopy.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    toCopy.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    toCopy.srcQueueFamilyIndex = toCopy.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    toCopy.image = m_image;
    toCopy.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 1, &pixelsReady, 1, &toCopy);

    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {m_width, m_height, 1};
    vkCmdCopyBufferToImage(cmd, m_pixels.handle(), m_image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);

    // The copy's writes to the display image -> the blit's reads of it.
    VkImageMemoryBarrier toBlit = toCopy;
    toBlit.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    toBlit.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    toBlit.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    toBlit.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &toBlit);
}

void ToneMapper::recordBlit(VkCommandBuffer cmd, VkImage target, VkOffset2D offset, VkExtent2D size) const {
    VkImageBlit blit{};
    blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.srcOffsets[1] = {int32_t(m_width), int32_t(m_height), 1};
    blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.dstOffsets[0] = {offset.x, offset.y, 0};
    blit.dstOffsets[1] = {offset.x + int32_t(size.width), offset.y + int32_t(size.height), 1};
    const bool sameSize = size.width == m_width && size.height == m_height;
    vkCmdBlitImage(cmd, m_image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                   1, &blit, sameSize ? VK_FILTER_NEAREST : m_filter);
}

std::vector<uint8_t> ToneMapper::readRgb() const {
    std::vector<uint32_t> packed = m_pixels.read<uint32_t>();
    std::vector<uint8_t> rgb(size_t(m_width) * m_height * 3);
    for (size_t i = 0; i < size_t(m_width) * m_height; ++i) {
        rgb[3 * i + 0] = uint8_t(packed[i] & 0xff);
        rgb[3 * i + 1] = uint8_t((packed[i] >> 8) & 0xff);
        rgb[3 * i + 2] = uint8_t((packed[i] >> 16) & 0xff);
    }
    return rgb;
}

}  // namespace penumbra::preview
#endif  // PENUMBRA_HAVE_GLFW
