// Small scenes skip the BVH: every primitive goes into the kernel as specialization
// constants (shaders/geometry/inline_geometry.glsl) and every ray tests each in turn.
// Where that pays was measured (docs/PERFORMANCE.md, "Round 8"). The price: the kernel
// depends on the coordinates, so each distinct small geometry compiles its own pipeline
// (a batch sweeping one pays per job); keeping them in a uniform buffer instead, so that
// pipelines depend on the shape types alone, was measured slower (same section).
#pragma once

#include <cstdint>
#include <vector>

#include "render/scene_arrays.h"

namespace penumbra {

// Whether the kernel holds the scene's primitives inline.
enum class InlineGeometry {
    Rule,  // inline where inlineGeometryPays says so (every render)
    Off,   // always the BVH (tests and benchmarks compare)
};

// Whether `arrays` is small enough for the inline path to beat the BVH.
bool inlineGeometryPays(const SceneArrays& arrays);

// How many tests the inline kernel for `count` (1 to INLINE_MAX_PRIMITIVES) primitives
// unrolls: the smallest multiple of INLINE_CAPACITY_STEP that holds them. The kernel is the
// variant "<kernel>_inline<capacity>" that cmake/EmbedShaders.cmake compiles.
uint32_t inlineKernelCapacity(uint32_t count);

// The INLINE_PRIMITIVE_WORDS words of each of `primitives` (in leaf order, as the kernel
// indexes them; shared/types.h), for SPEC_INLINE_FIRST onwards; at most
// INLINE_MAX_PRIMITIVES primitives.
std::vector<uint32_t> inlineGeometryWords(const std::vector<gpu::Primitive>& primitives);

}  // namespace penumbra
