// Drivers that end a shader's loops early. lavapipe before Mesa 25 (gallivm's
// LP_MAX_TGSI_LOOP_ITERATIONS) gives each run of a SIMD group 65535 loop iterations, every
// loop counted together, and then leaves every loop at the end of its current iteration,
// without a word. A render kernel that loops longer in one dispatch lost the rest of its
// work, and added the sample in flight half traced. Measured on 22.3.6: the tile queue
// (render/tile_queue.h), whose invocations go from pixel to pixel, was cut in every render
// of some size (1,024 invocations in the Cornell box at its own settings; a 32 x 32 film of
// 512 samples in one dispatch left 48-64 pixels short), and under load the emitter-first
// test (tests/test_emitter_first.cpp) saw the 16 pixels of two SIMD groups differ. With
// one pixel per invocation it takes a band of many long samples: a 37 x 35 film of 2048
// samples of four light and four BRDF samples each, in one dispatch, cut 368 invocations.
// Mesa 25.0.7 cut nothing.
// On such a driver the kernels are specialized (SPEC_LOOPS_MAY_BE_CUT) to notice a cut
// (integrators/kernel_common.glsl, loopsWereCut), add no sample that it touched, take each
// pixel's samples up from its own count, and count the cuts; Renderer::renderAll then
// renders what was left, and its dispatches are no tile queue. The image is the same, bit
// for bit, as where nothing is cut.
#pragma once

#include "gpu/context.h"

namespace penumbra {

// lavapipe older than Mesa 25, or of a version its driverInfo does not name (the checks cost
// a short loop per sample); no other device.
bool loopsMayBeCutFor(const gpu::DeviceInfo& device);

}  // namespace penumbra
