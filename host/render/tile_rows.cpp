// The tile-row interleave of render dispatches (see tile_rows.h).
#include "render/tile_rows.h"

#include <algorithm>
#include <cstdlib>

namespace penumbra {

uint32_t tileRowSlicesFor(const gpu::DeviceInfo& device, const char* lpNumThreads, unsigned hardwareThreads) {
    if (device.driverName != "llvmpipe") return 1;
    // More slices than lavapipe has threads would only cut each thread's share finer.
    constexpr unsigned long kMaxSlices = 64;
    if (lpNumThreads && *lpNumThreads) {
        char* end = nullptr;
        const unsigned long n = std::strtoul(lpNumThreads, &end, 10);
        // 0: lavapipe runs every workgroup on the submitting thread.
        if (*end == '\0' && lpNumThreads[0] != '-' && n <= kMaxSlices) return uint32_t(std::max(n, 1UL));
    }
    return uint32_t(std::clamp<unsigned long>(hardwareThreads, 1, kMaxSlices));
}

DispatchShape interleavedDispatch(uint32_t tileColumns, uint32_t tileRows, uint32_t slices) {
    DispatchShape shape;
    shape.x = tileColumns;
    shape.z = std::clamp<uint32_t>(slices, 1, std::max<uint32_t>(tileRows, 1));
    // Rows past the last (when Z does not divide them) are dispatched and return at once.
    shape.y = (tileRows + shape.z - 1) / shape.z;
    return shape;
}

}  // namespace penumbra
