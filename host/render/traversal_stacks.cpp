// Sizes for the traversal stacks' buffer and the dispatches it holds (see traversal_stacks.h).
#include "render/traversal_stacks.h"

#include <algorithm>

#include "shared/types.h"

namespace penumbra {

uint64_t invocationsOf(uint64_t workgroups) { return workgroups * TILE_PIXELS; }

uint32_t stackInvocationLimit(uint32_t entries) {
    const uint64_t fit = kStackBytes / (std::max<uint64_t>(entries, 1) * sizeof(uint32_t));
    return uint32_t(std::clamp<uint64_t>(fit, 1, kStackInvocations));
}

uint32_t stackInvocationsFor(uint32_t tileColumns, uint32_t tileRows, uint32_t limit) {
    const uint64_t row = invocationsOf(std::max<uint32_t>(tileColumns, 1));
    const uint64_t film = row * std::max<uint32_t>(tileRows, 1);
    return uint32_t(std::max(row, std::min<uint64_t>(film, limit)));
}

uint32_t tileRowsPerDispatch(uint32_t tileColumns, uint32_t invocations) {
    const uint64_t row = invocationsOf(std::max<uint32_t>(tileColumns, 1));
    return uint32_t(std::clamp<uint64_t>(invocations / row, 1, UINT32_MAX));
}

}  // namespace penumbra
