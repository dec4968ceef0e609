// A move-only storage/uniform buffer with its own memory. Prefers device-local memory;
// when that memory is not host-visible (discrete GPUs) uploads and downloads go through
// a temporary staging buffer, otherwise the memory is mapped directly (lavapipe, ReBAR).
#pragma once

#include <cstddef>
#include <cstring>
#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.h"

namespace penumbra::gpu {

// Throws GpuError("the NAME buffer needs N bytes, more than this device's LIMIT (M bytes)
// ...") when a buffer of `size` bytes for `usage` exceeds what the device can bind in one
// descriptor (maxStorageBufferRange, maxUniformBufferRange, maxTexelBufferElements for
// texel buffers viewed as 16-byte texels: the kernels bind whole buffers) or allocate at
// once (`maxAllocation`, maxMemoryAllocationSize; 0: unknown).
void checkBufferSize(std::string_view name, VkDeviceSize size, VkBufferUsageFlags usage,
                     const VkPhysicalDeviceLimits& limits, VkDeviceSize maxAllocation);

// The device address of `buffer` (vkGetBufferDeviceAddressKHR), which was created with
// VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT on a device with bufferDeviceAddress enabled.
VkDeviceAddress deviceAddressOf(VkDevice device, VkBuffer buffer);

// VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT where the Context's device has (and so has
// enabled) bufferDeviceAddress, else 0: for buffers that kernels may read by address.
VkBufferUsageFlags deviceAddressUsage(const Context& context);

class Buffer {
public:
    Buffer() = default;
    // `size` is rounded up to at least 16 bytes so that empty arrays can still be bound.
    // Throws GpuError, naming the buffer by `name`, when the device cannot hold it in one
    // allocation or bind it whole (checkBufferSize).
    Buffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags required = 0,
           VkMemoryPropertyFlags preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, std::string_view name = {});
    ~Buffer();
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    // A device-local storage buffer holding a copy of `data`.
    template <class T>
    static Buffer fromSpan(const Context& context, std::span<const T> data,
                           VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) {
        return fromSpan(context, data, std::string_view(), usage);
    }
    // The same, named for the message when it is too large (e.g. "BVH nodes").
    template <class T>
    static Buffer fromSpan(const Context& context, std::span<const T> data, std::string_view name,
                           VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) {
        Buffer buffer(context, data.size_bytes(), usage, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, name);
        if (!data.empty()) buffer.upload(data.data(), data.size_bytes());
        return buffer;
    }
    template <class T>
    static Buffer fromVector(const Context& context, const std::vector<T>& data,
                             VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) {
        return fromSpan<T>(context, std::span<const T>(data), std::string_view(), usage);
    }
    template <class T>
    static Buffer fromVector(const Context& context, const std::vector<T>& data, std::string_view name,
                             VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) {
        return fromSpan<T>(context, std::span<const T>(data), name, usage);
    }

    void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
    // Like upload, for data made on the fly: `fill` writes the `bytes` through a host pointer
    // (this buffer's memory when it is host-visible, else a staging buffer's), so that a
    // large array (an environment map's RGBA texels) needs no host copy of its own first.
    void write(VkDeviceSize bytes, const std::function<void(void*)>& fill, VkDeviceSize offset = 0);
    void download(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
    template <class T>
    std::vector<T> read() const {
        std::vector<T> out(size_t(m_size / sizeof(T)));
        download(out.data(), out.size() * sizeof(T));
        return out;
    }
    // Fills the whole buffer with zero bytes on the GPU.
    void clear();

    VkBuffer handle() const { return m_buffer; }
    VkDeviceSize size() const { return m_size; }

    // Where the shaders find the buffer through a buffer reference: 0 unless its usage had
    // VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT (allowed where the Context's device has
    // bufferDeviceAddress, which it then enables).
    VkDeviceAddress address() const { return m_address; }

private:
    void release();

    const Context* m_context = nullptr;
    VkBuffer m_buffer = VK_NULL_HANDLE;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
    VkDeviceSize m_size = 0;
    bool m_hostVisible = false;
    bool m_hostCoherent = false;
    VkDeviceAddress m_address = 0;
};

}  // namespace penumbra::gpu
