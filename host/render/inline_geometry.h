// Small scenes skip the BVH: every primitive goes into the kernel as specialization
// constants (shaders/geometry/inline_geometry.glsl) and every ray tests each in turn.
// Where that pays was measured (docs/performance-history/round-08.md). The price: the kernel
// depends on the coordinates, so each distinct small geometry compiles its own pipeline
// (a batch sweeping one pays per job); keeping them in a uniform buffer instead, so that
// pipelines depend on the shape types alone, was measured slower (same section).
#pragma once

#include <cstddef>
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

// A group's box is tested before its primitives when it holds at least this many and its
// area is below this share of the scene box's (docs/performance-history/round-09.md).
constexpr size_t kInlineGroupTestedFrom = 3;
constexpr float kInlineGroupTestedBelow = 0.5f;

// The specialization words of a scene's primitives inline (SPEC_INLINE_FIRST and
// SPEC_INLINE_GROUP_FIRST onwards; shared/types.h). The kernel's slots come in groups of
// INLINE_GROUP_SIZE, each behind a bounding box that it tests first where the box is small
// against the scene's: a driver that skips a branch no SIMD lane takes (Mesa >= 24.3) then
// skips the group's tests whenever none of its eight rays comes near. A group is a compact
// subtree of `bvh`'s binary tree, so the slots hold the primitives out of leaf order, each
// slot naming its primitive's leaf-order index (what Hit.primitive reports), and a group
// may end with empty slots.
// Empty (no slots) when the kernel traverses the BVH.
struct InlineGeometryWords {
    std::vector<uint32_t> slots;   // INLINE_PRIMITIVE_WORDS per slot, at most INLINE_MAX_PRIMITIVES slots
    std::vector<uint32_t> groups;  // INLINE_GROUP_WORDS per group: box lo, box hi (float bits), tested (0/1)

    uint32_t slotCount() const;  // SPEC_INLINE_COUNT; the kernel variant's capacity follows it
};
InlineGeometryWords inlineGeometryWords(const Bvh& bvh);

}  // namespace penumbra
