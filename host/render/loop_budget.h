// Drivers that end a shader's loops early. lavapipe before Mesa 25 (gallivm's
// LP_MAX_TGSI_LOOP_ITERATIONS) gives each run of a SIMD group 65535 loop iterations, every
// loop counted together, and then leaves every loop at the end of its current iteration,
// without a word. A render kernel that loops longer in one dispatch (the tile queue's
// invocations go from pixel to pixel, render/tile_queue.h; a band of many samples) would
// lose the rest of its work, and the sample in flight would be added half traced.
// Measured on 22.3.6: a 32 x 32 film of 512 samples in one tile-queue dispatch left 48-64
// pixels short, and under load the emitter-first test (tests/test_emitter_first.cpp) saw
// the 16 pixels of two SIMD groups differ; Mesa 25.0.7 lost nothing.
// On such a driver the kernels are specialized (SPEC_LOOPS_MAY_BE_CUT) to notice a cut
// (integrators/kernel_common.glsl, loopsWereCut), add no sample that it touched, take each
// pixel's samples up from its own count, and report the cut; Renderer::renderAll then renders
// what was left. The image is the same, bit for bit, as where nothing is cut.
#pragma once

#include "gpu/context.h"

namespace penumbra {

// lavapipe older than Mesa 25, or of a version its driverInfo does not name (the checks cost
// a short loop per sample); no other device.
bool loopsMayBeCutFor(const gpu::DeviceInfo& device);

}  // namespace penumbra
