// penumbra_texture_bench: how fast a compute kernel on this Vulkan device does bilinear,
// repeating texture lookups from (a) a sampled image (RGBA16F, linear filter, repeat,
// textureLod), (b) half texels in an RGBA32UI texel buffer filtered in the shader and (c)
// the texture inside an atlas image with wrap gutters, wrapped in the shader and sampled at
// unnormalized coordinates. The three alternate, runs times each, for a small and a large
// texture; medians of lookups per second. Kernel: shaders/texture.comp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>
#include <glm/gtc/packing.hpp>

#include "bench_harness.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/vk_check.h"
#include "shared/types.h"

namespace {

using penumbra::bench::BenchBinding;
using penumbra::bench::BenchKernel;
using penumbra::bench::kWorkgroup;
using penumbra::bench::loadAverage;
using penumbra::bench::median;
using penumbra::bench::readSpirv;
using penumbra::gpu::Buffer;
using penumbra::gpu::Context;
using penumbra::gpu::vkCheck;

struct Push {
    uint32_t width, height, steps, atlasX;
};

// An RGBA16F sampled image with its view and a linear sampler, filled from `halves`
// through a staging buffer. The sampler repeats at normalized coordinates, or
// (`unnormalized`) clamps to the edge at unnormalized ones.
class SampledImage {
public:
    SampledImage(const Context& context, uint32_t width, uint32_t height, const std::vector<uint16_t>& halves,
                 bool unnormalized = false)
        : m_device(context.device()) {
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
        vkCheck(vkCreateImage(m_device, &info, nullptr, &m_image), "create image");
        VkMemoryRequirements req;
        vkGetImageMemoryRequirements(m_device, m_image, &req);
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.allocationSize = req.size;
        alloc.memoryTypeIndex = context.findMemoryType(req.memoryTypeBits, 0);
        vkCheck(vkAllocateMemory(m_device, &alloc, nullptr, &m_memory), "allocate image memory");
        vkCheck(vkBindImageMemory(m_device, m_image, m_memory, 0), "bind image memory");

        Buffer staging(context, halves.size() * 2, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, 0, "texture staging");
        staging.upload(halves.data(), halves.size() * 2);
        context.submitAndWait([&](VkCommandBuffer cmd) {
            VkImageMemoryBarrier toCopy{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
            toCopy.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            toCopy.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
            toCopy.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            toCopy.srcQueueFamilyIndex = toCopy.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            toCopy.image = m_image;
            toCopy.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            // Nothing before: the image is new; the copy must wait for the layout change.
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
        vkCheck(vkCreateImageView(m_device, &view, nullptr, &m_view), "create image view");
        VkSamplerCreateInfo sampler{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
        sampler.magFilter = sampler.minFilter = VK_FILTER_LINEAR;
        sampler.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
        sampler.addressModeU = sampler.addressModeV = sampler.addressModeW =
            unnormalized ? VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE : VK_SAMPLER_ADDRESS_MODE_REPEAT;
        sampler.maxLod = 0.0f;
        sampler.unnormalizedCoordinates = unnormalized ? VK_TRUE : VK_FALSE;
        vkCheck(vkCreateSampler(m_device, &sampler, nullptr, &m_sampler), "create sampler");
    }
    ~SampledImage() {
        vkDestroySampler(m_device, m_sampler, nullptr);
        vkDestroyImageView(m_device, m_view, nullptr);
        vkDestroyImage(m_device, m_image, nullptr);
        vkFreeMemory(m_device, m_memory, nullptr);
    }
    SampledImage(const SampledImage&) = delete;
    SampledImage& operator=(const SampledImage&) = delete;

    VkDescriptorImageInfo descriptor() const { return {m_sampler, m_view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}; }

private:
    VkDevice m_device;
    VkImage m_image = VK_NULL_HANDLE;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
    VkImageView m_view = VK_NULL_HANDLE;
    VkSampler m_sampler = VK_NULL_HANDLE;
};

// The texture (size x size RGBA halves) in an atlas of (2 size + 2) x (size + 2) texels
// at (size + 1, 1), surrounded by a 1-texel gutter of its repeat neighbours (the opposite
// edge; corners the opposite corner); the left half of the atlas is empty. The offset makes
// the kernel add a large coordinate, as it would for a texture far into a real atlas.
std::vector<uint16_t> atlasOf(const std::vector<uint16_t>& halves, uint32_t size, uint32_t& atlasWidth) {
    atlasWidth = 2 * size + 2;
    std::vector<uint16_t> atlas(size_t(atlasWidth) * (size + 2) * 4, 0);
    for (uint32_t y = 0; y < size + 2; ++y)
        for (uint32_t x = 0; x < size + 2; ++x) {
            uint32_t sx = (x + size - 1) % size, sy = (y + size - 1) % size;  // gutter: wrapped
            std::memcpy(&atlas[(size_t(y) * atlasWidth + size + x) * 4], &halves[(size_t(sy) * size + sx) * 4], 8);
        }
    return atlas;
}

// One kernel variant: binding 0 = results, BINDING_TEXTURE_TEXELS = the texture (a sampled
// image or the texel buffer's RGBA32UI view), BINDING_MATERIAL_TEXTURES declared by
// textures.glsl but never read (bound to the same texel buffer).
std::unique_ptr<BenchKernel> makeVariant(const Context& context, const std::string& spirv, const SampledImage* image,
                                         VkBufferView texels, const Buffer& results, Push push, uint32_t invocations) {
    std::vector<BenchBinding> bindings(3);
    bindings[0].binding = 0;
    bindings[0].buffer = results.handle();
    bindings[1].binding = BINDING_TEXTURE_TEXELS;
    if (image) {
        bindings[1].type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        bindings[1].image = image->descriptor();
    } else {
        bindings[1].type = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
        bindings[1].texelView = texels;
    }
    bindings[2].binding = BINDING_MATERIAL_TEXTURES;
    bindings[2].type = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    bindings[2].texelView = texels;
    return std::make_unique<BenchKernel>(context, readSpirv(spirv, "penumbra_texture_bench"), bindings, &push,
                                         uint32_t(sizeof(Push)), invocations / kWorkgroup);
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 7;
    uint32_t invocations = 1u << 18, steps = 32;
    for (int i = 1; i + 1 < argc; i += 2) {
        std::string arg = argv[i];
        if (arg == "--runs") runs = std::stoi(argv[i + 1]);
        else if (arg == "--invocations") invocations = uint32_t(std::stoul(argv[i + 1])) / kWorkgroup * kWorkgroup;
        else if (arg == "--steps") steps = uint32_t(std::stoul(argv[i + 1]));
        else {
            std::fprintf(stderr, "usage: penumbra_texture_bench [--runs N] [--invocations N] [--steps N]\n");
            return 2;
        }
    }
    try {
        Context context;
        const auto& info = context.info();
        std::printf("Device: %s; driver: %s %s; load average at start: %s\n", info.name.c_str(),
                    info.driverName.c_str(), info.driverInfo.c_str(), loadAverage().c_str());
        std::printf("%u invocations x %u dependent lookups per run, %d runs alternating, medians\n\n", invocations,
                    steps, runs);
        std::printf(
            "| texture | (a) sampled image: M lookups/s | (b) texel buffer, bilinear in shader: M lookups/s | (c) "
            "atlas image, unnormalized, wrap in shader: M lookups/s | b / a | c / a | c / b | max |a - b|, |a - c|, "
            "first lookup |\n");
        std::printf("|---|---|---|---|---|---|---|---|\n");
        for (uint32_t size : {64u, 2048u}) {
            // Random RGBA in [0, 1) as half floats: the texture every variant reads.
            std::mt19937 rng(size);
            std::uniform_real_distribution<float> unit(0.0f, 1.0f);
            std::vector<uint16_t> halves(size_t(size) * size * 4);
            for (uint16_t& h : halves) h = glm::packHalf1x16(unit(rng));
            SampledImage image(context, size, size, halves);
            uint32_t atlasWidth = 0;
            SampledImage atlas(context, 2 * size + 2, size + 2, atlasOf(halves, size, atlasWidth), true);
            Buffer texels(context, halves.size() * 2, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, 0,
                          VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "texels");
            texels.upload(halves.data(), halves.size() * 2);
            VkBufferViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
            viewInfo.buffer = texels.handle();
            viewInfo.format = VK_FORMAT_R32G32B32A32_UINT;
            viewInfo.range = VK_WHOLE_SIZE;
            VkBufferView view = VK_NULL_HANDLE;
            vkCheck(vkCreateBufferView(context.device(), &viewInfo, nullptr, &view), "create texel view");
            const VkDeviceSize resultBytes = VkDeviceSize(invocations) * 16;
            Buffer resultsA(context, resultBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
            Buffer resultsB(context, resultBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
            Buffer resultsC(context, resultBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
            Push push{size, size, steps, size + 1};
            std::string dir = PENUMBRA_MICROBENCH_SPIRV_DIR;
            auto a = makeVariant(context, dir + "/texture_image.spv", &image, view, resultsA, push, invocations);
            auto b = makeVariant(context, dir + "/texture_texel.spv", nullptr, view, resultsB, push, invocations);
            auto c = makeVariant(context, dir + "/texture_atlas.spv", &atlas, view, resultsC, push, invocations);
            a->run();  // llvmpipe compiles on the first dispatch
            b->run();
            c->run();
            std::vector<double> ta, tb, tc;
            for (int r = 0; r < runs; ++r) {
                ta.push_back(a->run());
                tb.push_back(b->run());
                tc.push_back(c->run());
            }
            auto sa = resultsA.read<float>(), sb = resultsB.read<float>(), sc = resultsC.read<float>();
            double diffB = 0, diffC = 0;
            for (size_t i = 0; i < sa.size(); ++i)
                if (i % 4 != 3) {
                    diffB = std::max(diffB, double(std::fabs(sa[i] - sb[i])));
                    diffC = std::max(diffC, double(std::fabs(sa[i] - sc[i])));
                }
            double lookups = double(invocations) * steps;
            double ra = lookups / median(ta) * 1e-6, rb = lookups / median(tb) * 1e-6, rc = lookups / median(tc) * 1e-6;
            std::printf("| %u x %u RGBA16F (%.1f MiB) | %.1f | %.1f | %.1f | %.2f | %.2f | %.2f | %.3g, %.3g |\n", size,
                        size, double(halves.size()) * 2 / (1 << 20), ra, rb, rc, rb / ra, rc / ra, rc / rb, diffB,
                        diffC);
            std::fflush(stdout);
            vkDestroyBufferView(context.device(), view, nullptr);
        }
        std::printf("\nload average at end: %s\n", loadAverage().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra_texture_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
