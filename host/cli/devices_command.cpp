// `penumbra devices`: every Vulkan device the loader sees, the chosen one marked with '*',
// each followed by its driver and the driver's version where the device reports them
// (VK_KHR_driver_properties; for lavapipe the Mesa version, e.g. "Mesa 22.3.6 (LLVM 15.0.6)").
#include <cstdio>

#include <vulkan/vulkan.h>

#include "cli/commands.h"
#include "gpu/context.h"

namespace penumbra {

int devicesCommand() {
    int chosen = -1;
    auto devices = gpu::Context::listDevices(&chosen);
    if (devices.empty()) {
        std::fprintf(stderr, "penumbra: no Vulkan devices found\n");
        return 1;
    }
    for (const auto& d : devices) {
        std::printf("%c %u: %s (%s, Vulkan %u.%u%s)\n", int(d.index) == chosen ? '*' : ' ', d.index, d.name.c_str(),
                    d.type.c_str(), VK_API_VERSION_MAJOR(d.apiVersion), VK_API_VERSION_MINOR(d.apiVersion),
                    d.hasCompute ? "" : ", no compute queue");
        if (!d.driverName.empty())
            std::printf("    driver: %s, %s%s%s\n", d.driverName.c_str(), d.driverInfo.c_str(),
                        d.conformanceVersion.empty() ? "" : "; conformance ", d.conformanceVersion.c_str());
    }
    return 0;
}

}  // namespace penumbra
