// Interface of the light-BVH test kernel (shaders/tests/light_bvh.comp), shared by the
// kernel and tests/test_light_bvh_gpu.cpp: modes, push constants, the per-invocation record
// and the test's output binding (after the render kernels' BINDING_* numbers, so that the
// tree keeps BINDING_LIGHT_BVH).
#ifndef PENUMBRA_TESTS_LIGHT_BVH_TEST_H
#define PENUMBRA_TESTS_LIGHT_BVH_TEST_H

#include "shared/types.h"

#ifdef __cplusplus
namespace penumbra::gpu {
#endif

#define LIGHT_BVH_TEST_BINDING_OUT (BINDING_COUNT)
#define LIGHT_BVH_TEST_BINDING_COUNT (BINDING_COUNT + 1)

// PMF: record i holds the tree's pmf of item i at (p, n), replayed from the item's trail.
// SAMPLE: invocation i descends with u_i from the stateless rng (pixel 0, sample index i,
//   seed): the item reached, its sampled pmf and its trail's replayed pmf.
PENUMBRA_CONST uint LIGHT_BVH_TEST_MODE_PMF = 0u;
PENUMBRA_CONST uint LIGHT_BVH_TEST_MODE_SAMPLE = 1u;

PENUMBRA_CONST uint LIGHT_BVH_TEST_WORKGROUP_SIZE = 64u;

struct LightBvhTestPush {  // 48 bytes
    vec3 p;      // shading point
    uint mode;   // LIGHT_BVH_TEST_MODE_*
    vec3 n;      // shading normal (0: none)
    uint count;  // invocations that do work
    uint seed;
    uint itemsTexel;  // where the items start in the tree's texels
    uint pad0, pad1;
};

struct LightBvhTestRecord {  // 16 bytes
    uint item;
    float pmf;       // PMF: replayed; SAMPLE: as sampled
    float replayed;  // SAMPLE: the replayed pmf of the item reached
    float pad;
};

#ifdef __cplusplus
}  // namespace penumbra::gpu
#endif

#endif
