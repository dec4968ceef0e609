// `penumbra --version`: one line for bug reports and scripts, the program's version (the
// CMake project version) and the Vulkan device and driver a render would use, e.g.
//   penumbra 0.3.0; Vulkan device: llvmpipe (LLVM 15.0.6, 256 bits) (cpu), driver llvmpipe Mesa 25.0.7
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "gpu/context.h"

#ifndef PENUMBRA_VERSION
#error "PENUMBRA_VERSION comes from CMakeLists.txt's project(VERSION)"
#endif

namespace penumbra {

int versionCommand() {
    int chosen = -1;
    std::vector<gpu::DeviceInfo> devices;
    std::string why = "none found";
    try {
        devices = gpu::Context::listDevices(&chosen);
    } catch (const std::exception& e) {
        why = e.what();
    }
    std::string line = "penumbra " PENUMBRA_VERSION "; ";
    if (chosen < 0 || size_t(chosen) >= devices.size()) {
        // The version is still the answer asked for (exit 0); `penumbra devices` fails instead.
        line += "no Vulkan device (" + why + ")";
    } else {
        const gpu::DeviceInfo& d = devices[size_t(chosen)];
        line += "Vulkan device: " + d.name + " (" + d.type + ")";
        if (d.driverName.empty()) line += ", driver not reported (no VK_KHR_driver_properties)";
        else line += ", driver " + d.driverName + " " + d.driverInfo;
    }
    std::printf("%s\n", line.c_str());
    return 0;
}

}  // namespace penumbra
