// Interface of the sampler test kernel (shaders/tests/rng.comp), shared by the kernel and
// tests/test_sampler.cpp: the push-constant block and the layout of the output.
#ifndef PENUMBRA_TESTS_RNG_TEST_H
#define PENUMBRA_TESTS_RNG_TEST_H

#include "shared/types.h"

#ifdef __cplusplus
namespace penumbra::gpu {
#endif

PENUMBRA_CONST uint RNG_WORKGROUP_SIZE = 64u;

// 32 bytes: push-constant block of rng.comp. Invocation (i, j) draws sample index
// firstIndex + i of pixel firstPixel + j * pixelStride, calling rand2 dimensionCount
// times from dimension 0 (as an integrator does), and writes every pair:
//   out[(j * count + i) * dimensionCount + d] = the d-th rand2 of that sample.
struct RngPush {
    uint samplerType;  // SAMPLER_* (shared/types.h)
    uint seed;
    uint firstPixel;
    uint pixelStride;
    uint pixelCount;
    uint firstIndex;
    uint count;           // sample indices per pixel
    uint dimensionCount;  // rand2 calls per sample
};

#ifdef __cplusplus
}  // namespace penumbra::gpu
#endif

#endif
