// Specialization constants applied to SPIR-V before the driver sees it, and the code they
// rule out removed (SPIRV-Tools' optimizer, Debian's spirv-tools).
//
// Why: lavapipe turns SPIR-V into NIR and inlines every function call at every call site
// *before* it folds the constants, so each call of a function whose body a constant mostly
// removes (a strategy, a light kind, an empty inline-geometry slot) is first copied whole,
// then optimised away, on every pipeline creation. Folding the constants here, and pruning
// the branches and functions they decide, hands the driver only the code the scene runs:
// on the Cornell box the driver's work falls from 3.2 to 1.0 CPU seconds and its peak
// memory from 1.1 GB to 0.5 GB, with the same compiled kernel (docs/PERFORMANCE.md,
// "Start-up"). Only constant-deciding passes run: no inlining, no unrolling, no arithmetic
// rewriting, so the floating-point operations the driver sees are the shader's own.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace penumbra::gpu {

// `code` with constant_id i set to `values[i]` (raw 32-bit patterns) for every i the module
// declares, each spec constant turned into a plain constant, and the branches, functions
// and instructions that are then dead removed. Throws GpuError if the optimizer fails.
std::vector<uint32_t> specializeSpirv(std::span<const uint32_t> code, const std::vector<uint32_t>& values);

}  // namespace penumbra::gpu
