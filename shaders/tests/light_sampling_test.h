// Interface of the light-sampling test kernel (shaders/tests/light_sampling.comp), shared
// by the kernel and tests/test_light_sampling.cpp, tests/test_light_selection.cpp: modes,
// the push-constant block, the per-invocation record and the two test-only bindings, which
// come after the render kernels' BINDING_* numbers so that the scene buffers keep theirs.
#ifndef PENUMBRA_TESTS_LIGHT_SAMPLING_TEST_H
#define PENUMBRA_TESTS_LIGHT_SAMPLING_TEST_H

#include "shared/types.h"

#ifdef __cplusplus
namespace penumbra::gpu {
#endif

// Test-only bindings: directions in (mode PDF), records out. Both >= BINDING_COUNT.
#define LIGHT_TEST_BINDING_IN (BINDING_COUNT)
#define LIGHT_TEST_BINDING_OUT (BINDING_COUNT + 1)
#define LIGHT_TEST_BINDING_COUNT (BINDING_COUNT + 2)

// SAMPLE: invocation i draws sampleLight(light, x, n, u_i, modes) with u_i from the
//   stateless rng (pixel 0, sample index i, seed), then traces x + t wi through the scene
//   and evaluates lightPdf at that first hit (the consistency check).
// PDF: record i holds the pdf of wi = directions[i].xyz as the integrator sees it: the
//   first hit along wi must be the light (else 0), lightPdf there; the environment directly.
// SELECT: invocation i draws one entry of a selection table (light table through
//   selectLight, with the number left of the draw in tracedT, or the mesh-triangle
//   table through sampleAlias) with u_i.
PENUMBRA_CONST uint LIGHT_TEST_MODE_SAMPLE = 0u;
PENUMBRA_CONST uint LIGHT_TEST_MODE_PDF = 1u;
PENUMBRA_CONST uint LIGHT_TEST_MODE_SELECT = 2u;

PENUMBRA_CONST uint LIGHT_TEST_TABLE_LIGHTS = 0u;  // lightTable[] via selectLight
PENUMBRA_CONST uint LIGHT_TEST_TABLE_MESH = 1u;    // meshTable[] via sampleAlias

// LightTestRecord::flags
PENUMBRA_CONST uint LIGHT_TEST_ACCEPTED = 1u;   // sampleLight returned true
PENUMBRA_CONST uint LIGHT_TEST_DELTA = 2u;      // the sample is a delta light's
PENUMBRA_CONST uint LIGHT_TEST_HIT_LIGHT = 4u;  // the traced ray's first hit is the light

PENUMBRA_CONST uint LIGHT_TEST_WORKGROUP_SIZE = 64u;

// 80 bytes (std430 push constants).
struct LightTestPush {
    vec3 x;               // shading point
    uint mode;            // LIGHT_TEST_MODE_*
    vec3 n;               // unit shading normal (the environment samples about it)
    uint light;           // index into lights[]
    uint count;           // invocations that do work
    uint seed;            // SAMPLE, SELECT: rng seed
    uint sphereSampling;  // SPHERE_*
    uint table;           // SELECT: LIGHT_TEST_TABLE_*
    uint tableOffset;     // SELECT: the (sub-)table [tableOffset, tableOffset + tableCount)
    uint tableCount;
    uint quadSampling;      // QUAD_* (0, the zero-initialized push: area)
    uint triangleSampling;  // TRIANGLE_* (0: area)
    float minSolidAngle;     // the fallback bounds of LightSamplingModes
    float minElevationSine;
    uint besideFirst;  // the primitives beside the BVH's tree (geometry/bvh.glsl; set by LightKernel::run)
    uint besideCount;
};

// 48 bytes per invocation.
struct LightTestRecord {
    vec3 wi;            // SAMPLE: sampled direction, zero vector when sampleLight returned false
    float pdf;          // SAMPLE: pdf returned by sampleLight; PDF: the pdf at directions[i]
    vec3 radiance;      // SAMPLE: LightSample::radiance
    float dist;         // SAMPLE: LightSample::dist
    float tracedPdf;    // SAMPLE: lightPdf at the traced first hit (0 if not the light); SELECT: pmf
    float tracedT;      // SAMPLE, PDF: distance of the traced first hit (0 if none)
    uint hitPrimitive;  // SAMPLE, PDF: primitive of the traced first hit (NO_HIT if none); SELECT: item
    uint flags;         // SAMPLE: LIGHT_TEST_* bits; PDF: LIGHT_TEST_HIT_LIGHT
};

#ifdef __cplusplus
}  // namespace penumbra::gpu
#endif

#endif
