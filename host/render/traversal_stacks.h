// Where the "_address" kernels keep their BVH traversal stacks (shaders/geometry/bvh.glsl):
// a buffer of BVH_STACKS_PER_INVOCATION stacks of childStackDepth (host/bvh/bvh.h) 32-bit
// entries, child references, per invocation of a dispatch (one per ray that the kernel
// traverses together), reached through its device address instead of a local array.
// On lavapipe 25.0 a store to a local array at a per-lane index is a loop over the SIMD
// lanes with a branch on each lane's mask bit, which mispredicts as lanes push at random; a
// store through an address is one masked scatter (docs/performance-history/round-13.md).
// The buffer holds the stacks of one dispatch, so its size bounds a dispatch's invocations:
// a pass band that needs more is recorded as several dispatches of fewer tile rows, each
// followed by a barrier, since the next one reuses the same entries. A tile queue's few
// workgroups (render/tile_queue.h) fit in one.
#pragma once

#include <cstdint>

namespace penumbra {

// Invocations whose stacks the buffer holds where a film has more: 2^18 (a 512 x 512 film),
// fewer where their stacks would take more than kStackBytes (stackInvocationLimit).
inline constexpr uint32_t kStackInvocations = 1u << 18;
inline constexpr uint64_t kStackBytes = uint64_t(64) << 20;

// The most invocations whose stacks, `entries` 32-bit entries per invocation in all, fit in
// kStackBytes, at most kStackInvocations and at least 1: 2^18 up to 64 entries, 43,690 for
// the deepest tree the builder makes (BVH_STACKS_PER_INVOCATION stacks of 3 x BVH_MAX_DEPTH
// entries).
uint32_t stackInvocationLimit(uint32_t entries);

// Invocations of a dispatch of `workgroups` workgroups (of TILE_SIZE x TILE_SIZE).
uint64_t invocationsOf(uint64_t workgroups);

// The invocations the stacks' buffer holds for a film of `tileColumns` x `tileRows` tiles:
// the whole film up to kStackInvocations (`limit`), and never less than one row of tiles.
uint32_t stackInvocationsFor(uint32_t tileColumns, uint32_t tileRows, uint32_t limit = kStackInvocations);

// The most tile rows that one dispatch of `tileColumns` columns, one workgroup per tile,
// covers within `invocations`; at least 1 (stackInvocationsFor holds one row).
uint32_t tileRowsPerDispatch(uint32_t tileColumns, uint32_t invocations);

}  // namespace penumbra
