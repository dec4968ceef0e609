// Light selection "bvh" on the GPU (SCENE_FORMAT.md `light_selection`): the light BVH of
// render/light_bvh.h over the scene's lights, flattened into the one texel buffer the
// kernel reads at BINDING_LIGHT_BVH (shaders/lights/light_bvh.glsl), and the small
// selection table that picks, uniformly, one of the lights at infinity or the tree.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "render/light_bvh.h"

namespace penumbra {

struct SceneArrays;

struct LightBvhArrays {
    LightBvh tree;  // the host's copy, which tests compare the GPU's choices with
    // BINDING_LIGHT_BVH, RGBA32UI texels: node i is texels 3i .. 3i + 2, item i is texel
    // itemsTexel + i, and the trail of primitive p (leaf order) is half of texel
    // trailsTexel + p / 2 (xy for even p, zw for odd), for every emitting sphere, quad and
    // mesh triangle (the others hold zeros). Empty unless the selection is "bvh".
    std::vector<glm::uvec4> texels;
    uint32_t itemsTexel = 0, trailsTexel = 0;
    // lightTable[tableOffset, tableOffset + tableCount): the directional and environment
    // lights and, if it has an item, the tree (item NO_LIGHT), each with probability
    // 1 / tableCount, as pbrt-v4's BVHLightSampler gives them.
    uint32_t tableOffset = 0, tableCount = 0;
};

// The bounds of every light with a position in `arrays` (after finishAreaLights, so that
// primitives are in leaf order): points, spots, spheres, quads and each triangle of a mesh
// light. Lights with a position that emit nothing get power 0 (buildLightBvh drops them).
std::vector<LightBounds> lightBoundsOf(const SceneArrays& arrays);

// For each item of arrays.lightBvh.tree, the primitive (leaf order) by which a BRDF-sampled
// ray hits its emitter: a sphere's or quad's own, a mesh light's triangle; NO_HIT for point
// and spot lights. MIS finds the item's probability again from it.
std::vector<uint32_t> lightBvhHitPrimitives(const SceneArrays& arrays);

// Builds out.lightBvh and appends its table to out.lightTable (after buildLightSelection).
void buildLightBvhArrays(SceneArrays& out);

}  // namespace penumbra
