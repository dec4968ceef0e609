// Test entry point for shaders/common/rng.glsl: writes the rand2 values of chosen pixels,
// sample indices and dimensions, under either sampler, so the host can check their
// distribution (tests/test_sampler.cpp). Interface: tests/rng_test.h.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "shared/types.h"
#include "common/rng.glsl"
#include "tests/rng_test.h"

layout(local_size_x = RNG_WORKGROUP_SIZE) in;
layout(std430, binding = 0) writeonly restrict buffer Results { vec2 results[]; };
layout(push_constant) uniform PushBlock { RngPush push; };

void main() {
    uint i = gl_GlobalInvocationID.x, j = gl_GlobalInvocationID.y;
    if (i >= push.count || j >= push.pixelCount) return;
    Rng rng = makeRng(push.firstPixel + j * push.pixelStride, push.firstIndex + i, push.seed, push.samplerType);
    uint base = (j * push.count + i) * push.dimensionCount;
    for (uint d = 0u; d < push.dimensionCount; ++d) results[base + d] = rand2(rng);
}
