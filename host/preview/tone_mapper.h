// The preview's path from the accumulation buffer to the screen, all on the GPU: the
// tonemap.comp kernel writes sRGB-encoded RGBA8 pixels into a storage buffer, which is
// copied into a film-sized "display image" that is then blitted (scaled) into the
// swapchain image. The host sees the pixels only when asked for a screenshot.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/kernel.h"
#include "image/tone_map.h"

namespace penumbra::preview {

class ToneMapper {
public:
    // `accumulation` and `compensation` are the Renderer's buffers (AccumSum and
    // AccumCompensation per pixel, shared/types.h) of a
    // width x height film. `srgbImage`: the display image is R8G8B8A8_SRGB, for blits into
    // an *_SRGB swapchain (the blit decodes and re-encodes, so bytes are encoded once);
    // otherwise R8G8B8A8_UNORM, whose bytes a UNORM swapchain shows as they are.
    ToneMapper(const gpu::Context& context, const gpu::Buffer& accumulation, const gpu::Buffer& compensation,
               uint32_t width, uint32_t height, bool srgbImage);
    ~ToneMapper();
    ToneMapper(const ToneMapper&) = delete;
    ToneMapper& operator=(const ToneMapper&) = delete;

    // Records the tone map (times 2^look.exposure, then look.curve) and the copy into the display image, which
    // ends in TRANSFER_SRC_OPTIMAL. The accumulation's writes must already be visible to
    // compute-shader reads (Renderer::recordPasses ends with that barrier).
    void record(VkCommandBuffer cmd, ToneLook look) const;
    // Instead of the tone map: `packed` (RGBA8 as tonemap.comp writes them, one per pixel:
    // an AOV layer's picture, preview/layer_cycle.h) become the pixels, now (an upload
    // that waits; call while no frame is in flight), and recordShowPixels records the copy
    // of them into the display image, as record() does after its tone map.
    void setPixels(const std::vector<uint32_t>& packed);
    void recordShowPixels(VkCommandBuffer cmd) const;
    // Records a blit of the display image (after record()) into `target`, which must be in
    // TRANSFER_DST_OPTIMAL, filling the rectangle at `offset` of `size` pixels.
    void recordBlit(VkCommandBuffer cmd, VkImage target, VkOffset2D offset, VkExtent2D size) const;

    // The pixels of the last completed record() as 8-bit sRGB RGB, top row first: one
    // host copy, for --screenshot.
    std::vector<uint8_t> readRgb() const;

    bool srgbImage() const { return m_srgb; }
    uint32_t width() const { return m_width; }
    uint32_t height() const { return m_height; }

private:
    const gpu::Context& m_context;
    uint32_t m_width, m_height;
    bool m_srgb;
    VkFilter m_filter = VK_FILTER_NEAREST;
    gpu::Buffer m_pixels;  // uint per pixel, RGBA8
    gpu::Kernel m_kernel;
    VkImage m_image = VK_NULL_HANDLE;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
};

}  // namespace penumbra::preview
