// How a render dispatch shares the film's pixels among worker threads (see tile_queue.h).
#include "render/tile_queue.h"

#include <algorithm>
#include <cstdlib>

namespace penumbra {

uint32_t workerThreadsFor(const gpu::DeviceInfo& device, const char* lpNumThreads, unsigned hardwareThreads) {
    if (device.driverName != "llvmpipe") return 1;
    // Counting too many threads costs little (a workgroup more than lavapipe has threads
    // finds the queue empty), too few leaves a thread idle; 64 bounds what is believed.
    constexpr unsigned long kMaxThreads = 64;
    if (lpNumThreads && *lpNumThreads) {
        char* end = nullptr;
        const unsigned long n = std::strtoul(lpNumThreads, &end, 10);
        // 0: lavapipe runs every workgroup on the submitting thread.
        if (*end == '\0' && lpNumThreads[0] != '-' && n <= kMaxThreads) return uint32_t(std::max(n, 1UL));
    }
    return uint32_t(std::clamp<unsigned long>(hardwareThreads, 1, kMaxThreads));
}

uint32_t tileQueueWorkgroups(uint64_t tiles, uint32_t workers, uint32_t maxWorkgroups) {
    return uint32_t(std::max<uint64_t>(std::min<uint64_t>({tiles, workers, maxWorkgroups}), 1));
}

}  // namespace penumbra
