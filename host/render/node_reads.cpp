// Node reads per device (see node_reads.h).
#include "render/node_reads.h"

#include <cctype>

#include "shared/types.h"

namespace penumbra {

int mesaMajorVersion(const std::string& driverInfo) {
    const std::string prefix = "Mesa ";
    const size_t at = driverInfo.find(prefix);
    if (at == std::string::npos) return 0;
    int major = 0;
    size_t i = at + prefix.size();
    size_t digits = 0;
    for (; i < driverInfo.size() && std::isdigit(static_cast<unsigned char>(driverInfo[i])) && digits < 4;
         ++i, ++digits)
        major = major * 10 + (driverInfo[i] - '0');
    return digits > 0 ? major : 0;
}

namespace {
// The address reads are the 32-byte loads through a buffer reference: both features.
bool canReadByAddress(const gpu::DeviceInfo& device) { return device.shaderInt64 && device.bufferDeviceAddress; }
}  // namespace

uint32_t nodeReadsFor(const gpu::DeviceInfo& device) {
    // The version where the texel fetch became a call lies between the two measured
    // (22.3 and 25.0); the untested ones in between keep 22.3's choice.
    constexpr int kFirstStorageMesa = 25;
    if (device.driverName == "llvmpipe") {
        const int major = mesaMajorVersion(device.driverInfo);
        if (major > 0 && major < kFirstStorageMesa) return NODE_READS_TEXELS;
        if (canReadByAddress(device)) return NODE_READS_ADDRESS;
    }
    return device.shaderInt64 ? NODE_READS_STORAGE_32 : NODE_READS_STORAGE;
}

std::string nodeReadsKernel(const std::string& base, uint32_t nodeReads) {
    if (nodeReads == NODE_READS_STORAGE_32) return base + "_int64";
    if (nodeReads == NODE_READS_ADDRESS) return base + "_address";
    return base;
}

uint32_t nodeReadsValue(NodeReads mode, const gpu::DeviceInfo& device) {
    switch (mode) {
        case NodeReads::Texels: return NODE_READS_TEXELS;
        case NodeReads::Storage: return NODE_READS_STORAGE;
        case NodeReads::Storage32: return device.shaderInt64 ? NODE_READS_STORAGE_32 : NODE_READS_STORAGE;
        case NodeReads::Address:
            if (canReadByAddress(device)) return NODE_READS_ADDRESS;
            return nodeReadsValue(NodeReads::Storage32, device);
        case NodeReads::Device: break;
    }
    return nodeReadsFor(device);
}

}  // namespace penumbra
