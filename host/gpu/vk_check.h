// Turns a failed VkResult into an exception whose one-line message says what was
// attempted and why it failed, e.g. "failed to create compute pipeline (VK_ERROR_OUT_OF_DEVICE_MEMORY)".
#pragma once

#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace penumbra::gpu {

// A Vulkan failure: exit status 1 on the command line (not the user's input at fault).
class GpuError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

const char* resultName(VkResult result);

inline void vkCheck(VkResult result, const char* attempted) {
    if (result != VK_SUCCESS)
        throw GpuError(std::string("failed to ") + attempted + " (" + resultName(result) + ")");
}

}  // namespace penumbra::gpu
