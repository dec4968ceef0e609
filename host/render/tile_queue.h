// How a render dispatch shares the film's pixels among a CPU device's worker threads.
// lavapipe (Mesa's lp_cs_tpool) splits a dispatch's workgroups, in order, into one
// contiguous range per worker thread, fixed before any runs (iter_per_thread = num_iters /
// num_threads). With one workgroup per tile, a thread whose range costs less, or that the
// operating system ran for longer, finishes first and waits for the other: on the
// 1M-triangle bench scene the render kept 1.43 of 2 cores busy with the tiles in order,
// and 1.82-1.88 with the tile rows interleaved over the threads (docs/performance-history/round-11.md and
// docs/performance-history/round-20.md).
// So on such a device a dispatch is a tile queue: one workgroup per worker thread, whose
// invocations each take the band's next pixel from an atomic counter until none is left
// (integrators/kernel_common.glsl, main). The thread that would have waited renders pixels
// from the other's share instead: 1.97-1.99 cores busy, 1.08-1.10x the samples per
// wall-clock second on the million triangles, for the same CPU time. A pixel's samples do
// not depend on which invocation renders it, so the image is the same bit for bit
// (TileQueue.EveryWorkerCountGivesTheSameImage).
// GPUs hand workgroups to cores as they become free, so there one workgroup renders one tile.
// So do lavapipes before Mesa 25, which end a SIMD group's loops after 65535 iterations: the
// queue's few workgroups would have that budget for a whole band (render/loop_budget.h).
#pragma once

#include <cstdint>

#include "gpu/context.h"

namespace penumbra {

// lavapipe's worker threads on `device`: LP_NUM_THREADS where `lpNumThreads` (its value, or
// null) is a number from 0 to 64 (0: the submitting thread alone, counted as 1), else
// `hardwareThreads` (what lavapipe starts by default, one per CPU); 1 for every other
// device. The tile queue is used where this is more than 1.
uint32_t workerThreadsFor(const gpu::DeviceInfo& device, const char* lpNumThreads, unsigned hardwareThreads);

// Whether a dispatch on a device with `workers` worker threads is a tile queue.
inline bool usesTileQueue(uint32_t workers) { return workers > 1; }

// The workgroups of a tile queue over `tiles` tiles: one per worker thread, as lavapipe gives
// each thread its share of them, but never more than there are tiles nor more than
// `maxWorkgroups` (what the traversal stacks hold); at least 1.
uint32_t tileQueueWorkgroups(uint64_t tiles, uint32_t workers, uint32_t maxWorkgroups);

}  // namespace penumbra
