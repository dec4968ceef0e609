// Interface of the BSDF test kernel (shaders/tests/bsdf_sampling.comp), shared by the kernel
// and tests/test_bsdf_sampling.cpp: modes, the push-constant block and the records.
#ifndef PENUMBRA_TESTS_BSDF_SAMPLING_TEST_H
#define PENUMBRA_TESTS_BSDF_SAMPLING_TEST_H

#include "shared/types.h"

#ifdef __cplusplus
namespace penumbra::gpu {
#endif

// SAMPLE: invocation i draws bsdfSample(material, n, wo, u) with u from the stateless rng
//   (pixel 0, sample index i, seed), as the integrator does:
//   out.a = (wi, returned pdf), zero when it returned false; out.b.x = bsdfPdf(wi);
//   out.b.yzw = the returned f minus bsdfEval(wi).
// PDF:  out.a.x = bsdfPdf(material, n, wo, in.a.xyz).
// EVAL: out.a.xyz = bsdfEval(material, n, in.a.xyz, in.b.xyz) (wo = in.a, wi = in.b) and
//   out.b.xyz = the same with the directions swapped (reciprocity).
PENUMBRA_CONST uint BSDF_TEST_MODE_SAMPLE = 0u;
PENUMBRA_CONST uint BSDF_TEST_MODE_PDF = 1u;
PENUMBRA_CONST uint BSDF_TEST_MODE_EVAL = 2u;

PENUMBRA_CONST uint BSDF_TEST_WORKGROUP_SIZE = 64u;

// 80 bytes (std430 push constants).
struct BsdfTestPush {
    Material material;
    vec3 n;      // unit shading normal
    uint mode;   // BSDF_TEST_MODE_*
    vec3 wo;     // unit outgoing direction (SAMPLE, PDF)
    uint count;  // invocations that do work
    uint seed;
    uint pad0, pad1, pad2;
};

// 32 bytes: the input and the output record of one invocation.
struct BsdfTestRecord {
    vec4 a;
    vec4 b;
};

#ifdef __cplusplus
}  // namespace penumbra::gpu
#endif

#endif
