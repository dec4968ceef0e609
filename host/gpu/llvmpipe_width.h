// How many SIMD lanes llvmpipe (lavapipe's code generator) gives a kernel: 8 (256-bit
// vectors) by default, 16 where LP_NATIVE_VECTOR_WIDTH=512 asks for them. The choice is an
// environment variable that the driver reads when it loads and again when it compiles a
// kernel, so it is made before the Vulkan instance exists (gpu/context.cpp) and kept for the
// process's life; other drivers ignore it.
#pragma once

namespace penumbra::gpu {

// Sets LP_NATIVE_VECTOR_WIDTH=512 on Intel CPUs with AVX-512 (F, BW, DQ, VL), unless the
// user set it or MESA_SHADER_CACHE_DIR, or `presents` (the preview). There, 16 lanes
// rendered 1.30x the samples per second on a million triangles and 1.18x on the Cornell
// box, where an AMD EPYC (Zen 4, whose AVX-512 runs a 512-bit operation in two halves)
// measured 0.91-1.01x (docs/PERFORMANCE.md, "Round 22"). Images are the same bit for bit.
// - Mesa 25.0.7's shader cache does not key its kernels by the width: a process at one
//   width loads what a process at the other compiled, which measured as slow as 8 lanes
//   and, once, rendered garbage. So the choice comes with a shader cache of its own,
//   MESA_SHADER_CACHE_DIR = $XDG_CACHE_HOME (or ~/.cache)/penumbra/llvmpipe-512.
// - The preview keeps 8 lanes: with 16, llvmpipe 25.0.7 stops it with a bus error while it
//   presents.
// - The processes this one starts inherit the variables, marked PENUMBRA_LLVMPIPE_WIDTH, so
//   that a penumbra among them, the preview included, makes its own choice.
void chooseLlvmpipeVectorWidth(bool presents);

}  // namespace penumbra::gpu
