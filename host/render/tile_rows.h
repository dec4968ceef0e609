// How a render dispatch lays the film's tiles out over its workgroups, so that every
// worker thread of a CPU device gets an equal share of the costly parts of the image.
// lavapipe (Mesa's lp_cs_tpool) splits a dispatch's workgroups, in order (x fastest, then
// y, then z), into one contiguous range per worker thread, decided before any runs: with
// rows in order, each thread gets a horizontal band of the film, and the one with the sky
// finishes first and waits. Measured on the 1M-triangle bench scene (2 threads), the render
// used 1.4 of its 2 cores (docs/PERFORMANCE.md, "Round 11").
// So the dispatch's z interleaves tile rows: slice z of Z holds the tile rows z, z + Z,
// z + 2Z, ...; with Z equal to the worker threads, thread i gets slice i, a set of rows
// spread over the whole film (integrators/kernel_common.glsl, invocationPixel).
// Each pixel still gets the same samples: only which thread runs it changes.
#pragma once

#include <cstdint>

#include "gpu/context.h"

namespace penumbra {

// The workgroup counts of one dispatch.
struct DispatchShape {
    uint32_t x = 1, y = 1, z = 1;
};

// The interleave (Z) for `device`: lavapipe's worker threads, that is LP_NUM_THREADS where
// `lpNumThreads` (its value, or null) is a number from 0 to 64 (0: one thread), else `hardwareThreads`
// (what lavapipe starts by default, one per CPU); 1 for every other device, whose
// hardware hands workgroups out as cores become free.
uint32_t tileRowSlicesFor(const gpu::DeviceInfo& device, const char* lpNumThreads, unsigned hardwareThreads);

// The dispatch for `tileColumns` x `tileRows` tiles, interleaving rows over at most
// `slices` z-slices (never more than there are rows).
DispatchShape interleavedDispatch(uint32_t tileColumns, uint32_t tileRows, uint32_t slices);

}  // namespace penumbra
