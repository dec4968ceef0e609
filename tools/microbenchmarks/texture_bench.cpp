// penumbra_texture_bench: how fast a compute kernel on this Vulkan device does bilinear,
// repeating texture lookups from (a) a sampled image (RGBA16F, linear filter, repeat,
// textureLod) and (b) the renderer's path, half texels in an RGBA32UI texel buffer filtered
// in the shader (shaders/textures/textures.glsl). The two alternate, runs times each, for
// a small and a large texture; medians of lookups per second. Kernel: shaders/texture.comp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>
#include <glm/gtc/packing.hpp>

#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/vk_check.h"
#include "shared/types.h"

namespace {

using penumbra::gpu::Buffer;
using penumbra::gpu::Context;
using penumbra::gpu::vkCheck;

constexpr uint32_t kWorkgroup = 64;

struct Push {
    uint32_t width, height, steps, pad;
};

std::vector<uint32_t> readSpirv(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw std::runtime_error("cannot read " + path + " (build the penumbra_texture_bench target)");
    std::vector<uint32_t> words(size_t(in.tellg()) / 4);
    in.seekg(0);
    in.read(reinterpret_cast<char*>(words.data()), std::streamsize(words.size() * 4));
    return words;
}

// An RGBA16F sampled image with its view and a linear, repeating sampler, filled from
// `halves` through a staging buffer.
class SampledImage {
public:
    SampledImage(const Context& context, uint32_t width, uint32_t height, const std::vector<uint16_t>& halves)
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
        sampler.addressModeU = sampler.addressModeV = sampler.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
        sampler.maxLod = 0.0f;
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

// One kernel variant: binding 0 = results, BINDING_TEXTURE_TEXELS = the texture (a sampled
// image or the texel buffer's RGBA32UI view), BINDING_MATERIAL_TEXTURES declared by
// textures.glsl but never read (bound to the same texel buffer).
class Variant {
public:
    Variant(const Context& context, const std::string& spirv, const SampledImage* image, VkBufferView texels,
            const Buffer& results, Push push, uint32_t invocations)
        : m_context(context), m_push(push), m_groups(invocations / kWorkgroup) {
        VkDevice device = context.device();
        auto code = readSpirv(spirv);
        VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = code.size() * 4;
        moduleInfo.pCode = code.data();
        vkCheck(vkCreateShaderModule(device, &moduleInfo, nullptr, &m_module), "create shader module");
        const VkDescriptorType textureType = image ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
                                                   : VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
        VkDescriptorSetLayoutBinding bindings[3] = {
            {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
            {BINDING_TEXTURE_TEXELS, textureType, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
            {BINDING_MATERIAL_TEXTURES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT,
             nullptr}};
        VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        setInfo.bindingCount = 3;
        setInfo.pBindings = bindings;
        vkCheck(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &m_setLayout), "create set layout");
        VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Push)};
        VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        layoutInfo.setLayoutCount = 1;
        layoutInfo.pSetLayouts = &m_setLayout;
        layoutInfo.pushConstantRangeCount = 1;
        layoutInfo.pPushConstantRanges = &range;
        vkCheck(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &m_layout), "create pipeline layout");
        VkComputePipelineCreateInfo pipelineInfo{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        pipelineInfo.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        pipelineInfo.stage.module = m_module;
        pipelineInfo.stage.pName = "main";
        pipelineInfo.layout = m_layout;
        vkCheck(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipelineInfo, nullptr, &m_pipeline),
                "create compute pipeline");

        VkDescriptorPoolSize sizes[3] = {
            {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1}, {textureType, 1}, {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1}};
        VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        poolInfo.maxSets = 1;
        poolInfo.poolSizeCount = 3;
        poolInfo.pPoolSizes = sizes;
        vkCheck(vkCreateDescriptorPool(device, &poolInfo, nullptr, &m_pool), "create descriptor pool");
        VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        alloc.descriptorPool = m_pool;
        alloc.descriptorSetCount = 1;
        alloc.pSetLayouts = &m_setLayout;
        vkCheck(vkAllocateDescriptorSets(device, &alloc, &m_set), "allocate descriptor set");
        VkDescriptorBufferInfo resultInfo{results.handle(), 0, VK_WHOLE_SIZE};
        VkDescriptorImageInfo imageInfo{};
        if (image) imageInfo = image->descriptor();
        VkWriteDescriptorSet writes[3] = {{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                          {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                          {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
        writes[0].dstSet = m_set;
        writes[0].dstBinding = 0;
        writes[0].descriptorCount = 1;
        writes[0].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[0].pBufferInfo = &resultInfo;
        writes[1].dstSet = m_set;
        writes[1].dstBinding = BINDING_TEXTURE_TEXELS;
        writes[1].descriptorCount = 1;
        writes[1].descriptorType = textureType;
        if (image) writes[1].pImageInfo = &imageInfo;
        else writes[1].pTexelBufferView = &texels;
        writes[2].dstSet = m_set;
        writes[2].dstBinding = BINDING_MATERIAL_TEXTURES;
        writes[2].descriptorCount = 1;
        writes[2].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
        writes[2].pTexelBufferView = &texels;
        vkUpdateDescriptorSets(device, 3, writes, 0, nullptr);
    }
    ~Variant() {
        VkDevice device = m_context.device();
        vkDestroyDescriptorPool(device, m_pool, nullptr);
        vkDestroyPipeline(device, m_pipeline, nullptr);
        vkDestroyPipelineLayout(device, m_layout, nullptr);
        vkDestroyDescriptorSetLayout(device, m_setLayout, nullptr);
        vkDestroyShaderModule(device, m_module, nullptr);
    }
    Variant(const Variant&) = delete;
    Variant& operator=(const Variant&) = delete;

    // Seconds for one dispatch over all invocations, submitted and waited for.
    double run() const {
        auto start = std::chrono::steady_clock::now();
        m_context.submitAndWait([&](VkCommandBuffer cmd) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_pipeline);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_layout, 0, 1, &m_set, 0, nullptr);
            vkCmdPushConstants(cmd, m_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Push), &m_push);
            vkCmdDispatch(cmd, m_groups, 1, 1);
        });
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }

private:
    const Context& m_context;
    Push m_push;
    uint32_t m_groups;
    VkShaderModule m_module = VK_NULL_HANDLE;
    VkDescriptorSetLayout m_setLayout = VK_NULL_HANDLE;
    VkPipelineLayout m_layout = VK_NULL_HANDLE;
    VkPipeline m_pipeline = VK_NULL_HANDLE;
    VkDescriptorPool m_pool = VK_NULL_HANDLE;
    VkDescriptorSet m_set = VK_NULL_HANDLE;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    std::string a, b, c;
    in >> a >> b >> c;
    return a + ", " + b + ", " + c;
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
            "| texture | (a) sampled image: M lookups/s | (b) texel buffer, bilinear in shader: M lookups/s | b / a | "
            "max |a - b|, first lookup |\n");
        std::printf("|---|---|---|---|---|\n");
        for (uint32_t size : {64u, 2048u}) {
            // Random RGBA in [0, 1) as half floats: the texture both variants read.
            std::mt19937 rng(size);
            std::uniform_real_distribution<float> unit(0.0f, 1.0f);
            std::vector<uint16_t> halves(size_t(size) * size * 4);
            for (uint16_t& h : halves) h = glm::packHalf1x16(unit(rng));
            SampledImage image(context, size, size, halves);
            Buffer texels(context, halves.size() * 2, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, 0,
                          VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "texels");
            texels.upload(halves.data(), halves.size() * 2);
            VkBufferViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
            viewInfo.buffer = texels.handle();
            viewInfo.format = VK_FORMAT_R32G32B32A32_UINT;
            viewInfo.range = VK_WHOLE_SIZE;
            VkBufferView view = VK_NULL_HANDLE;
            vkCheck(vkCreateBufferView(context.device(), &viewInfo, nullptr, &view), "create texel view");
            Buffer resultsA(context, VkDeviceSize(invocations) * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
            Buffer resultsB(context, VkDeviceSize(invocations) * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
            Push push{size, size, steps, 0};
            std::string dir = PENUMBRA_MICROBENCH_SPIRV_DIR;
            Variant a(context, dir + "/texture_image.spv", &image, view, resultsA, push, invocations);
            Variant b(context, dir + "/texture_texel.spv", nullptr, view, resultsB, push, invocations);
            a.run();  // llvmpipe compiles on the first dispatch
            b.run();
            std::vector<double> ta, tb;
            for (int r = 0; r < runs; ++r) {
                ta.push_back(a.run());
                tb.push_back(b.run());
            }
            auto sa = resultsA.read<float>(), sb = resultsB.read<float>();
            double diff = 0;
            for (size_t i = 0; i < sa.size(); ++i)
                if (i % 4 != 3) diff = std::max(diff, double(std::fabs(sa[i] - sb[i])));
            double lookups = double(invocations) * steps;
            double ra = lookups / median(ta) * 1e-6, rb = lookups / median(tb) * 1e-6;
            std::printf("| %u x %u RGBA16F (%.1f MiB) | %.1f | %.1f | %.2f | %.3g |\n", size, size,
                        double(halves.size()) * 2 / (1 << 20), ra, rb, rb / ra, diff);
            vkDestroyBufferView(context.device(), view, nullptr);
        }
        std::printf("\nload average at end: %s\n", loadAverage().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra_texture_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
