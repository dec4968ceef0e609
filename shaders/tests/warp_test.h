// Interface of the warp test kernel (shaders/tests/warp.comp), shared by the kernel and
// tests/test_warp.cpp: the warp ids, the two modes and the push-constant block.
// Other sampling tests (lights, BSDFs) follow the same pattern with their own kernels:
// mode SAMPLE writes (sample, pdf at the sample), mode PDF evaluates the pdf at points.
#ifndef PENUMBRA_TESTS_WARP_TEST_H
#define PENUMBRA_TESTS_WARP_TEST_H

#include "shared/types.h"

#ifdef __cplusplus
namespace penumbra::gpu {
#endif

PENUMBRA_CONST uint WARP_MODE_SAMPLE = 0u;  // out[i] = (sample of u_i, pdf at that sample)
PENUMBRA_CONST uint WARP_MODE_PDF = 1u;     // out[i].x = pdf at points[i]

// Warp ids. Directions: out = (x, y, z, pdf in solid angle). Disk: (x, y, 0, pdf in area).
// Triangle: (b0, b1, b2, pdf in area). `param` is the warp's parameter where it has one.
PENUMBRA_CONST uint WARP_UNIFORM_HEMISPHERE = 0u;
PENUMBRA_CONST uint WARP_COSINE_HEMISPHERE = 1u;
PENUMBRA_CONST uint WARP_PHONG_LOBE = 2u;         // param = exponent n
PENUMBRA_CONST uint WARP_UNIFORM_SPHERE = 3u;
PENUMBRA_CONST uint WARP_UNIFORM_CONE = 4u;       // param = cos(thetaMax)
PENUMBRA_CONST uint WARP_UNIFORM_CONE_1M = 5u;    // param = 1 - cos(thetaMax)
PENUMBRA_CONST uint WARP_UNIFORM_DISK = 6u;
PENUMBRA_CONST uint WARP_UNIFORM_TRIANGLE = 7u;   // param = triangle area

PENUMBRA_CONST uint WARP_WORKGROUP_SIZE = 256u;

// 16 bytes: push-constant block of warp.comp.
struct WarpPush {
    uint mode;
    uint warp;
    uint count;  // number of samples (SAMPLE) or points (PDF)
    uint seed;   // SAMPLE: rng seed; sample index = invocation id
    float param;
    uint pad0, pad1, pad2;
};

#ifdef __cplusplus
}  // namespace penumbra::gpu
#endif

#endif
