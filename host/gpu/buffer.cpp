// Buffer allocation and host <-> device transfers.
#include "gpu/buffer.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>

#include "gpu/vk_check.h"

namespace penumbra::gpu {

namespace {

std::string byteText(VkDeviceSize bytes) {
    char text[64];
    if (bytes >= (VkDeviceSize(1) << 20))
        std::snprintf(text, sizeof text, "%.1f MiB, %llu bytes", double(bytes) / double(1 << 20),
                      static_cast<unsigned long long>(bytes));
    else std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
    return text;
}

}  // namespace

void checkBufferSize(std::string_view name, VkDeviceSize size, VkBufferUsageFlags usage,
                     const VkPhysicalDeviceLimits& limits, VkDeviceSize maxAllocation) {
    auto refuseText = [&](const char* limit, const std::string& value) {
        throw GpuError("the " + (name.empty() ? std::string("GPU") : std::string(name)) + " buffer needs " +
                       byteText(size) + ", more than this device's " + limit + " (" + value +
                       "); render a smaller film or scene, or use a device with a larger limit");
    };
    auto refuse = [&](const char* limit, VkDeviceSize value) { refuseText(limit, byteText(value)); };
    if ((usage & VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) && size > limits.maxStorageBufferRange)
        refuse("maxStorageBufferRange", limits.maxStorageBufferRange);
    if ((usage & VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT) && size > limits.maxUniformBufferRange)
        refuse("maxUniformBufferRange", limits.maxUniformBufferRange);
    // Texel buffers are viewed whole as 16-byte RGBA32UI texels (Kernel::bind).
    const VkBufferUsageFlags texels = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                                      VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT;
    if ((usage & texels) && size / 16 > limits.maxTexelBufferElements)
        refuseText("maxTexelBufferElements", std::to_string(limits.maxTexelBufferElements) + " texels of 16 bytes");
    if (maxAllocation > 0 && size > maxAllocation) refuse("maxMemoryAllocationSize", maxAllocation);
}

VkDeviceAddress deviceAddressOf(VkDevice device, VkBuffer buffer) {
    auto getAddress =
        reinterpret_cast<PFN_vkGetBufferDeviceAddressKHR>(vkGetDeviceProcAddr(device, "vkGetBufferDeviceAddressKHR"));
    if (!getAddress) throw GpuError("this Vulkan device gives no buffer device addresses (bufferDeviceAddress)");
    VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    info.buffer = buffer;
    return getAddress(device, &info);
}

VkBufferUsageFlags deviceAddressUsage(const Context& context) {
    return context.info().bufferDeviceAddress ? VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT : 0;
}

Buffer::Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags required,
               VkMemoryPropertyFlags preferred, std::string_view name)
    : m_context(&context), m_size(std::max<VkDeviceSize>(size, 16)) {
    // Before anything is created: beyond these limits Vulkan's behaviour is undefined
    // (lavapipe would bind a truncated range and render a silently wrong image).
    checkBufferSize(name, m_size, usage, context.limits(), context.maxAllocationSize());
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = m_size;
    info.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkDevice device = context.device();
    vkCheck(vkCreateBuffer(device, &info, nullptr, &m_buffer), "create buffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, m_buffer, &req);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = context.findMemoryType(req.memoryTypeBits, required, preferred);
    // A buffer read through its device address needs memory allocated for that.
    VkMemoryAllocateFlagsInfo allocFlags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    allocFlags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    if (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) alloc.pNext = &allocFlags;
    VkResult result = vkAllocateMemory(device, &alloc, nullptr, &m_memory);
    if (result != VK_SUCCESS) {
        release();
        vkCheck(result, ("allocate " + std::to_string(req.size >> 20) + " MiB of GPU memory").c_str());
    }
    vkCheck(vkBindBufferMemory(device, m_buffer, m_memory, 0), "bind buffer memory");
    VkMemoryPropertyFlags flags = context.memoryTypeFlags(alloc.memoryTypeIndex);
    m_hostVisible = flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    m_hostCoherent = flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) m_address = deviceAddressOf(device, m_buffer);
}

Buffer::~Buffer() { release(); }

void Buffer::release() {
    if (!m_context) return;
    if (m_buffer) vkDestroyBuffer(m_context->device(), m_buffer, nullptr);
    if (m_memory) vkFreeMemory(m_context->device(), m_memory, nullptr);
    m_buffer = VK_NULL_HANDLE;
    m_memory = VK_NULL_HANDLE;
}

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
    if (this != &other) {
        release();
        m_context = std::exchange(other.m_context, nullptr);
        m_buffer = std::exchange(other.m_buffer, VK_NULL_HANDLE);
        m_memory = std::exchange(other.m_memory, VK_NULL_HANDLE);
        m_size = std::exchange(other.m_size, 0);
        m_hostVisible = other.m_hostVisible;
        m_hostCoherent = other.m_hostCoherent;
        m_address = std::exchange(other.m_address, 0);
    }
    return *this;
}

void Buffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    const auto copy = [&](void* mapped) { std::memcpy(mapped, data, bytes); };
    write(bytes, copy, offset);
}

void Buffer::write(VkDeviceSize bytes, const std::function<void(void*)>& fill, VkDeviceSize offset) {
    if (bytes == 0) return;
    if (offset + bytes > m_size) throw GpuError("buffer upload out of range");
    VkDevice device = m_context->device();
    if (m_hostVisible) {
        void* mapped = nullptr;
        vkCheck(vkMapMemory(device, m_memory, offset, bytes, 0, &mapped), "map buffer memory");
        fill(mapped);
        if (!m_hostCoherent) {
            VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, m_memory, 0, VK_WHOLE_SIZE};
            vkFlushMappedMemoryRanges(device, 1, &range);
        }
        vkUnmapMemory(device, m_memory);
        return;
    }
    Buffer staging(*m_context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, 0);
    staging.write(bytes, fill);
    m_context->submitAndWait([&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, offset, bytes};
        vkCmdCopyBuffer(cmd, staging.handle(), m_buffer, 1, &region);
    });
}

void Buffer::download(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
    if (bytes == 0) return;
    if (offset + bytes > m_size) throw GpuError("buffer download out of range");
    VkDevice device = m_context->device();
    if (m_hostVisible) {
        void* mapped = nullptr;
        vkCheck(vkMapMemory(device, m_memory, offset, bytes, 0, &mapped), "map buffer memory");
        if (!m_hostCoherent) {
            VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, m_memory, 0, VK_WHOLE_SIZE};
            vkInvalidateMappedMemoryRanges(device, 1, &range);
        }
        std::memcpy(data, mapped, bytes);
        vkUnmapMemory(device, m_memory);
        return;
    }
    Buffer staging(*m_context, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, 0);
    m_context->submitAndWait([&](VkCommandBuffer cmd) {
        VkBufferCopy region{offset, 0, bytes};
        vkCmdCopyBuffer(cmd, m_buffer, staging.handle(), 1, &region);
    });
    staging.download(data, bytes);
}

void Buffer::clear() {
    m_context->submitAndWait([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, m_buffer, 0, VK_WHOLE_SIZE, 0); });
}

}  // namespace penumbra::gpu
