// Which drivers end loops early (see loop_budget.h).
#include "render/loop_budget.h"

#include "render/node_reads.h"

namespace penumbra {

bool loopsMayBeCutFor(const gpu::DeviceInfo& device) {
    // 22.3 cuts and 25.0 does not (loop_budget.h); the versions between are not measured and
    // keep the checks.
    constexpr int kFirstWholeLoopsMesa = 25;
    if (device.driverName != "llvmpipe") return false;
    const int major = mesaMajorVersion(device.driverInfo);
    return major == 0 || major < kFirstWholeLoopsMesa;
}

}  // namespace penumbra
