// The Vulkan instance, the chosen physical device, one logical device with one compute
// queue, and a command pool. Everything else on the GPU side borrows from a Context.
// Device choice: PENUMBRA_DEVICE / --device N if given, else a discrete GPU, else the
// first device (lavapipe on a machine without a GPU).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace penumbra::gpu {

struct DeviceInfo {
    uint32_t index = 0;
    std::string name;
    std::string type;  // "discrete", "integrated", "virtual", "cpu", "other"
    uint32_t apiVersion = 0;
    bool hasCompute = false;
    // From VkPhysicalDeviceDriverProperties where the device has VK_KHR_driver_properties
    // (lavapipe: "llvmpipe", "Mesa 22.3.6 (LLVM 15.0.6)"); empty otherwise.
    std::string driverName;
    std::string driverInfo;
    std::string conformanceVersion;  // "1.3.1.1", or empty
    // The shaderInt64 feature: 64-bit integers in shaders, which the Context enables where
    // the device has them (the kernels' "_int64" variants load BVH nodes 32 bytes at a time).
    bool shaderInt64 = false;
    // The bufferDeviceAddress feature (VK_KHR_buffer_device_address), which the Context
    // enables where the device has it (the "_address" kernels read nodes through it).
    bool bufferDeviceAddress = false;
};

struct ContextOptions {
    int deviceIndex = -1;  // -1 = automatic choice (see above)
    // Extra instance extensions, e.g. the window system's surface extensions (preview).
    std::vector<const char*> instanceExtensions;
    // If set, called once the instance exists; the queue family must then also be able to
    // present to the returned surface, and VK_KHR_swapchain is enabled on the device.
    std::function<VkSurfaceKHR(VkInstance)> createSurface;
};

class Context {
public:
    explicit Context(const ContextOptions& options = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    // All Vulkan devices the loader sees, in enumeration order (the --device numbering),
    // and the index the automatic choice would pick.
    static std::vector<DeviceInfo> listDevices(int* chosen = nullptr);

    VkInstance instance() const { return m_instance; }
    VkPhysicalDevice physicalDevice() const { return m_physicalDevice; }
    VkDevice device() const { return m_device; }
    VkQueue queue() const { return m_queue; }
    uint32_t queueFamily() const { return m_queueFamily; }
    VkCommandPool commandPool() const { return m_commandPool; }
    VkSurfaceKHR surface() const { return m_surface; }
    const DeviceInfo& info() const { return m_info; }
    const VkPhysicalDeviceLimits& limits() const { return m_limits; }
    // maxMemoryAllocationSize (Vulkan 1.1): the largest single allocation; 0 if not reported.
    VkDeviceSize maxAllocationSize() const { return m_maxAllocationSize; }

    // Index of a memory type with all `required` flags (and `preferred` ones if possible).
    uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                            VkMemoryPropertyFlags preferred = 0) const;
    VkMemoryPropertyFlags memoryTypeFlags(uint32_t type) const;

    // Records commands with `record` into a one-time command buffer, submits it and waits.
    void submitAndWait(const std::function<void(VkCommandBuffer)>& record) const;

private:
    // Destroys what exists (device after waiting for it, surface, instance) and nulls the
    // handles; safe to call on a half-built Context, and twice.
    void release() noexcept;

    VkInstance m_instance = VK_NULL_HANDLE;
    VkSurfaceKHR m_surface = VK_NULL_HANDLE;
    VkPhysicalDevice m_physicalDevice = VK_NULL_HANDLE;
    VkDevice m_device = VK_NULL_HANDLE;
    VkQueue m_queue = VK_NULL_HANDLE;
    uint32_t m_queueFamily = 0;
    VkCommandPool m_commandPool = VK_NULL_HANDLE;
    VkFence m_fence = VK_NULL_HANDLE;
    DeviceInfo m_info;
    VkPhysicalDeviceLimits m_limits{};
    VkDeviceSize m_maxAllocationSize = 0;
    VkPhysicalDeviceMemoryProperties m_memory{};
};

}  // namespace penumbra::gpu
