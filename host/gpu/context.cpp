// Vulkan instance / device creation and the automatic device choice.
#include "gpu/context.h"

#include <cstdlib>
#include <string>

#include "core/errors.h"
#include "gpu/llvmpipe_width.h"
#include "gpu/shader_objects.h"
#include "gpu/vk_check.h"

namespace penumbra::gpu {
namespace {

const char* deviceTypeName(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
        default: return "other";
    }
}

// Lower is better: discrete GPUs first, the CPU (lavapipe) last.
int deviceRank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
    }
}

VkInstance createInstance(const std::vector<const char*>& extensions) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "penumbra";
    app.pEngineName = "penumbra";
    // 1.3 where the loader has it, for VK_EXT_shader_object (gpu/shader_objects.h), which
    // needs dynamic rendering, core in 1.3; the kernels themselves need only 1.1.
    uint32_t loader = VK_API_VERSION_1_0;
    if (vkEnumerateInstanceVersion(&loader) != VK_SUCCESS) loader = VK_API_VERSION_1_0;
    app.apiVersion = loader >= VK_API_VERSION_1_3 ? VK_API_VERSION_1_3 : VK_API_VERSION_1_1;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    VkInstance instance = VK_NULL_HANDLE;
    VkResult result = vkCreateInstance(&info, nullptr, &instance);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw GpuError("no Vulkan device found (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER); "
                       "install a Vulkan driver, e.g. Debian's mesa-vulkan-drivers for lavapipe");
    vkCheck(result, "create Vulkan instance");
    return instance;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
    uint32_t count = 0;
    vkCheck(vkEnumeratePhysicalDevices(instance, &count, nullptr), "enumerate Vulkan devices");
    std::vector<VkPhysicalDevice> devices(count);
    vkCheck(vkEnumeratePhysicalDevices(instance, &count, devices.data()), "enumerate Vulkan devices");
    devices.resize(count);
    return devices;
}

// First queue family with compute (and presentation to `surface`, if given); -1 if none.
int computeQueueFamily(VkPhysicalDevice device, VkSurfaceKHR surface) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
    for (uint32_t i = 0; i < count; ++i) {
        if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
        if (surface != VK_NULL_HANDLE) {
            VkBool32 present = VK_FALSE;
            if (vkGetPhysicalDeviceSurfaceSupportKHR(device, i, surface, &present) != VK_SUCCESS || !present)
                continue;
        }
        return int(i);
    }
    return -1;
}

bool hasDeviceExtension(VkPhysicalDevice device, const char* name) {
    uint32_t count = 0;
    if (vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr) != VK_SUCCESS) return false;
    std::vector<VkExtensionProperties> extensions(count);
    if (vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data()) != VK_SUCCESS) return false;
    for (const auto& e : extensions)
        if (std::string(e.extensionName) == name) return true;
    return false;
}

DeviceInfo describe(VkPhysicalDevice device, uint32_t index) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(device, &props);
    DeviceInfo info;
    info.index = index;
    info.name = props.deviceName;
    info.type = deviceTypeName(props.deviceType);
    info.apiVersion = props.apiVersion;
    info.hasCompute = computeQueueFamily(device, VK_NULL_HANDLE) >= 0;
    VkPhysicalDeviceFeatures features;
    vkGetPhysicalDeviceFeatures(device, &features);
    info.shaderInt64 = features.shaderInt64 == VK_TRUE;
    // One query of the optional features, each struct chained only where its extension is.
    VkPhysicalDeviceBufferDeviceAddressFeaturesKHR address{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES_KHR};
    VkPhysicalDeviceShaderObjectFeaturesEXT shaderObject{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_OBJECT_FEATURES_EXT};
    VkPhysicalDeviceFeatures2 features2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    const bool hasAddress = hasDeviceExtension(device, VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME);
    const bool hasShaderObject = props.apiVersion >= VK_API_VERSION_1_3 &&
                                 hasDeviceExtension(device, VK_EXT_SHADER_OBJECT_EXTENSION_NAME);
    if (hasAddress) {
        address.pNext = features2.pNext;
        features2.pNext = &address;
    }
    if (hasShaderObject) {
        shaderObject.pNext = features2.pNext;
        features2.pNext = &shaderObject;
    }
    if (features2.pNext) vkGetPhysicalDeviceFeatures2(device, &features2);
    info.bufferDeviceAddress = hasAddress && address.bufferDeviceAddress == VK_TRUE;
    info.shaderObject = hasShaderObject && shaderObject.shaderObject == VK_TRUE;
    if (info.shaderObject) {
        VkPhysicalDeviceShaderObjectPropertiesEXT binary{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_OBJECT_PROPERTIES_EXT};
        VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        props2.pNext = &binary;
        vkGetPhysicalDeviceProperties2(device, &props2);
        std::copy(std::begin(binary.shaderBinaryUUID), std::end(binary.shaderBinaryUUID),
                  info.shaderBinaryUuid.begin());
        info.shaderBinaryVersion = binary.shaderBinaryVersion;
    }
    if (hasDeviceExtension(device, VK_KHR_DRIVER_PROPERTIES_EXTENSION_NAME)) {
        VkPhysicalDeviceDriverPropertiesKHR driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES_KHR};
        VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        props2.pNext = &driver;
        vkGetPhysicalDeviceProperties2(device, &props2);
        info.driverName = driver.driverName;
        info.driverInfo = driver.driverInfo;
        const auto& c = driver.conformanceVersion;
        if (c.major || c.minor || c.subminor || c.patch)
            info.conformanceVersion = std::to_string(c.major) + "." + std::to_string(c.minor) + "." +
                                      std::to_string(c.subminor) + "." + std::to_string(c.patch);
    }
    return info;
}

// The device index from PENUMBRA_DEVICE, or -1. Digits only, at most 9 of them: strtol
// into an int turned 4294967296 into device 0 and saturated a 20-digit value. A value
// that is no index is bad usage (exit status 2), as a bad --device is.
int deviceFromEnvironment() {
    const char* text = std::getenv("PENUMBRA_DEVICE");
    if (!text || !*text) return -1;
    const std::string value = text;
    if (value.size() > 9 || value.find_first_not_of("0123456789") != std::string::npos)
        throw InputError("PENUMBRA_DEVICE: not a device index: '" + elide(value) +
                         "' (a whole number from 0; see 'penumbra devices')");
    return std::stoi(value);
}

int automaticChoice(const std::vector<VkPhysicalDevice>& devices, VkSurfaceKHR surface) {
    int best = -1, bestRank = 1 << 30;
    for (size_t i = 0; i < devices.size(); ++i) {
        if (computeQueueFamily(devices[i], surface) < 0) continue;
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(devices[i], &props);
        if (deviceRank(props.deviceType) < bestRank) {
            bestRank = deviceRank(props.deviceType);
            best = int(i);
        }
    }
    return best;
}

// Sets llvmpipe's SIMD width before the instance that renders is created (see
// llvmpipe_width.h): the driver's version, on which the choice depends, is asked of a first
// instance at the driver's own width, gone before the second is created. Costs that first
// instance's start-up only where 16 lanes might pay (an Intel CPU with AVX-512).
void chooseLlvmpipeWidth(bool presents) {
    if (!llvmpipeWidthChoiceOpen(presents)) return;
    VkInstance probe = VK_NULL_HANDLE;
    try {
        probe = createInstance({});
    } catch (const GpuError&) {
        return;  // the instance that renders reports it
    }
    bool pays = false;
    try {
        const auto devices = physicalDevices(probe);
        const bool intel = cpuIsIntelWithAvx512();
        for (uint32_t i = 0; i < devices.size() && !pays; ++i) {
            const DeviceInfo info = describe(devices[i], i);
            pays = sixteenLanesPay(intel, info.driverName, info.driverInfo);
        }
    } catch (const GpuError&) {
        pays = false;
    }
    vkDestroyInstance(probe, nullptr);
    if (pays) askForSixteenLanes();
}

}  // namespace

std::vector<DeviceInfo> Context::listDevices(int* chosen) {
    chooseLlvmpipeWidth(false);  // as a render would have it: the width is in llvmpipe's name
    VkInstance instance = createInstance({});
    std::vector<DeviceInfo> result;
    try {
        auto devices = physicalDevices(instance);
        for (uint32_t i = 0; i < devices.size(); ++i) result.push_back(describe(devices[i], i));
        if (chosen) {
            int fromEnv = deviceFromEnvironment();
            *chosen = fromEnv >= 0 ? fromEnv : automaticChoice(devices, VK_NULL_HANDLE);
        }
    } catch (...) {
        vkDestroyInstance(instance, nullptr);
        throw;
    }
    vkDestroyInstance(instance, nullptr);
    return result;
}

Context::Context(const ContextOptions& options) {
    // A constructor that throws runs no destructor, while the members' own destructors do
    // run: the handles made so far are released by this guard, exactly once.
    struct ReleaseUnlessDone {
        Context* context;
        bool done = false;
        ~ReleaseUnlessDone() {
            if (!done) context->release();
        }
    } guard{this};
    chooseLlvmpipeWidth(bool(options.createSurface));
    m_instance = createInstance(options.instanceExtensions);
    if (options.createSurface) m_surface = options.createSurface(m_instance);
    auto devices = physicalDevices(m_instance);
    if (devices.empty())
        throw GpuError(
            "no Vulkan device found; install a Vulkan driver, e.g. Debian's mesa-vulkan-drivers for lavapipe");
    int index = options.deviceIndex >= 0 ? options.deviceIndex : deviceFromEnvironment();
    const std::string missing = "Vulkan device " + std::to_string(index) + " does not exist (" +
                                std::to_string(devices.size()) + " found; see 'penumbra devices')";
    // PENUMBRA_DEVICE out of range is bad usage (exit status 2), as a value that is no index.
    if (options.deviceIndex < 0 && index >= int(devices.size())) throw InputError("PENUMBRA_DEVICE: " + missing);
    if (index >= int(devices.size())) throw GpuError(missing);
    if (index < 0) index = automaticChoice(devices, m_surface);
    if (index < 0)
        throw GpuError(m_surface ? "no Vulkan device can both compute and present to the window"
                                 : "no Vulkan device has a compute queue");
    m_physicalDevice = devices[size_t(index)];
    m_info = describe(m_physicalDevice, uint32_t(index));
    int family = computeQueueFamily(m_physicalDevice, m_surface);
    if (family < 0)
        throw GpuError("Vulkan device " + std::to_string(index) + " (" + m_info.name + ") " +
                       (m_surface ? "cannot both compute and present to the window" : "has no compute queue"));
    m_queueFamily = uint32_t(family);

    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(m_physicalDevice, &props);
    m_limits = props.limits;
    if (props.apiVersion >= VK_API_VERSION_1_1) {
        VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
        VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        props2.pNext = &maintenance3;
        vkGetPhysicalDeviceProperties2(m_physicalDevice, &props2);
        m_maxAllocationSize = maintenance3.maxMemoryAllocationSize;
    }
    vkGetPhysicalDeviceMemoryProperties(m_physicalDevice, &m_memory);

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = m_queueFamily;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    std::vector<const char*> deviceExtensions;
    if (m_surface) deviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    VkPhysicalDeviceBufferDeviceAddressFeaturesKHR addressFeatures{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES_KHR};
    addressFeatures.bufferDeviceAddress = VK_TRUE;  // capture-replay and multi-device stay off
    if (m_info.bufferDeviceAddress) deviceExtensions.push_back(VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME);
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    if (m_info.bufferDeviceAddress) deviceInfo.pNext = &addressFeatures;
    const bool shaderObjects = options.shaderObjects && kernelsAsShaderObjects(m_info);
    VkPhysicalDeviceShaderObjectFeaturesEXT shaderObjectFeatures{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_OBJECT_FEATURES_EXT};
    shaderObjectFeatures.shaderObject = VK_TRUE;
    if (shaderObjects) {
        deviceExtensions.push_back(VK_EXT_SHADER_OBJECT_EXTENSION_NAME);
        shaderObjectFeatures.pNext = const_cast<void*>(deviceInfo.pNext);
        deviceInfo.pNext = &shaderObjectFeatures;
    }
    VkPhysicalDeviceFeatures enabledFeatures{};
    enabledFeatures.shaderInt64 = m_info.shaderInt64 ? VK_TRUE : VK_FALSE;
    deviceInfo.pEnabledFeatures = &enabledFeatures;
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    deviceInfo.enabledExtensionCount = uint32_t(deviceExtensions.size());
    deviceInfo.ppEnabledExtensionNames = deviceExtensions.data();
    vkCheck(vkCreateDevice(m_physicalDevice, &deviceInfo, nullptr, &m_device),
            ("create a logical device on " + m_info.name).c_str());
    vkGetDeviceQueue(m_device, m_queueFamily, 0, &m_queue);
    if (shaderObjects) {
        ShaderObjectFunctions f;
        f.create = reinterpret_cast<PFN_vkCreateShadersEXT>(vkGetDeviceProcAddr(m_device, "vkCreateShadersEXT"));
        f.destroy = reinterpret_cast<PFN_vkDestroyShaderEXT>(vkGetDeviceProcAddr(m_device, "vkDestroyShaderEXT"));
        f.binaryData =
            reinterpret_cast<PFN_vkGetShaderBinaryDataEXT>(vkGetDeviceProcAddr(m_device, "vkGetShaderBinaryDataEXT"));
        f.bind = reinterpret_cast<PFN_vkCmdBindShadersEXT>(vkGetDeviceProcAddr(m_device, "vkCmdBindShadersEXT"));
        if (f.create && f.destroy && f.binaryData && f.bind) m_shaderObjects = f;
    }

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = m_queueFamily;
    vkCheck(vkCreateCommandPool(m_device, &poolInfo, nullptr, &m_commandPool), "create command pool");
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    vkCheck(vkCreateFence(m_device, &fenceInfo, nullptr, &m_fence), "create fence");
    guard.done = true;
}

Context::~Context() { release(); }

void Context::release() noexcept {
    if (m_device) {
        vkDeviceWaitIdle(m_device);
        if (m_fence) vkDestroyFence(m_device, m_fence, nullptr);
        if (m_commandPool) vkDestroyCommandPool(m_device, m_commandPool, nullptr);
        vkDestroyDevice(m_device, nullptr);
    }
    if (m_surface) vkDestroySurfaceKHR(m_instance, m_surface, nullptr);
    if (m_instance) vkDestroyInstance(m_instance, nullptr);
    m_device = VK_NULL_HANDLE;
    m_surface = VK_NULL_HANDLE;
    m_instance = VK_NULL_HANDLE;
    m_fence = VK_NULL_HANDLE;
    m_commandPool = VK_NULL_HANDLE;
}

uint32_t Context::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                                 VkMemoryPropertyFlags preferred) const {
    for (int pass = 0; pass < 2; ++pass) {
        VkMemoryPropertyFlags wanted = pass == 0 ? (required | preferred) : required;
        for (uint32_t i = 0; i < m_memory.memoryTypeCount; ++i)
            if ((typeBits & (1u << i)) && (m_memory.memoryTypes[i].propertyFlags & wanted) == wanted)
                return i;
    }
    throw GpuError("failed to find a suitable Vulkan memory type");
}

VkMemoryPropertyFlags Context::memoryTypeFlags(uint32_t type) const {
    return m_memory.memoryTypes[type].propertyFlags;
}

void Context::submitAndWait(const std::function<void(VkCommandBuffer)>& record) const {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = m_commandPool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vkCheck(vkAllocateCommandBuffers(m_device, &alloc, &cmd), "allocate command buffer");
    try {
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vkCheck(vkBeginCommandBuffer(cmd, &begin), "begin command buffer");
        record(cmd);
        vkCheck(vkEndCommandBuffer(cmd), "end command buffer");
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &cmd;
        vkCheck(vkResetFences(m_device, 1, &m_fence), "reset fence");
        vkCheck(vkQueueSubmit(m_queue, 1, &submit, m_fence), "submit work to the GPU");
        vkCheck(vkWaitForFences(m_device, 1, &m_fence, VK_TRUE, UINT64_MAX), "wait for the GPU");
    } catch (...) {
        vkFreeCommandBuffers(m_device, m_commandPool, 1, &cmd);
        throw;
    }
    vkFreeCommandBuffers(m_device, m_commandPool, 1, &cmd);
}

}  // namespace penumbra::gpu
