// Ray counting for benchmarks (rays per second): with SPEC_COUNT_RAYS set, every trace
// call adds one to this invocation's tally, which kernel_common.glsl's main() adds to
// the ray-count buffer. Without it the counter is dead code and compiled out.
#ifndef PENUMBRA_RAY_COUNT_GLSL
#define PENUMBRA_RAY_COUNT_GLSL

#include "common/specialization.glsl"

uint raysTraced = 0u;

void countRay() {
    if (kCountRays != 0u) ++raysTraced;
}

#endif
