// An RGBA16F 2D image that kernels sample at unnormalized texel coordinates with a linear
// filter (the texture atlas, shaders/textures/textures.glsl): image, memory, view and
// sampler, filled once through a staging buffer and left in SHADER_READ_ONLY_OPTIMAL.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include <vulkan/vulkan.h>

#include "gpu/context.h"

namespace penumbra::gpu {

class SampledImage {
public:
    // `halves`: width x height RGBA half floats, row 0 first. Throws GpuError, naming the
    // image by `name`, when the device cannot hold an image that large
    // (maxImageDimension2D, maxMemoryAllocationSize).
    SampledImage(const Context& context, uint32_t width, uint32_t height, std::span<const uint16_t> halves,
                 std::string_view name);
    ~SampledImage();
    SampledImage(const SampledImage&) = delete;
    SampledImage& operator=(const SampledImage&) = delete;

    // For a VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER binding.
    VkDescriptorImageInfo descriptor() const { return {m_sampler, m_view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}; }

private:
    void release() noexcept;

    const Context& m_context;
    VkImage m_image = VK_NULL_HANDLE;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
    VkImageView m_view = VK_NULL_HANDLE;
    VkSampler m_sampler = VK_NULL_HANDLE;
};

}  // namespace penumbra::gpu
