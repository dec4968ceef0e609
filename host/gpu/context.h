// The Vulkan instance, the chosen physical device, one logical device with one compute
// queue, and a command pool. Everything else on the GPU side borrows from a Context.
// Device choice: PENUMBRA_DEVICE / --device N if given, else a discrete GPU, else the
// first device (lavapipe on a machine without a GPU).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/vk_shader_object.h"

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
    // The shaderObject feature (VK_EXT_shader_object, device API 1.3 or later), and the
    // UUID and version its binaries carry: where gpu/shader_objects.h uses shader objects,
    // the Context enables it.
    bool shaderObject = false;
    std::array<uint8_t, VK_UUID_SIZE> shaderBinaryUuid{};
    uint32_t shaderBinaryVersion = 0;
};

// The VK_EXT_shader_object entry points, loaded where the Context enables the extension.
struct ShaderObjectFunctions {
    PFN_vkCreateShadersEXT create = nullptr;
    PFN_vkDestroyShaderEXT destroy = nullptr;
    PFN_vkGetShaderBinaryDataEXT binaryData = nullptr;
    PFN_vkCmdBindShadersEXT bind = nullptr;
};

struct ContextOptions {
    int deviceIndex = -1;  // -1 = automatic choice (see above)
    // Extra instance extensions, e.g. the window system's surface extensions (preview).
    std::vector<const char*> instanceExtensions;
    // If set, called once the instance exists; the queue family must then also be able to
    // present to the returned surface, and VK_KHR_swapchain is enabled on the device.
    std::function<VkSurfaceKHR(VkInstance)> createSurface;
    // Kernels as shader objects where gpu/shader_objects.h says they pay; false keeps compute
    // pipelines everywhere (the tests compare the two).
    bool shaderObjects = true;
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
    // The shader-object entry points where kernels are shader objects (gpu/shader_objects.h),
    // else null.
    const ShaderObjectFunctions* shaderObjects() const { return m_shaderObjects ? &*m_shaderObjects : nullptr; }
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
    std::optional<ShaderObjectFunctions> m_shaderObjects;
    VkPhysicalDeviceLimits m_limits{};
    VkDeviceSize m_maxAllocationSize = 0;
    VkPhysicalDeviceMemoryProperties m_memory{};
};

}  // namespace penumbra::gpu
