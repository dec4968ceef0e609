// The light BVH of `light_selection: "bvh"` (Conty Estevez and Kulla 2018, "Importance
// Sampling of Many Lights with Adaptive Tree Splitting"; pbrt-v4's BVHLightSampler,
// src/pbrt/lightsamplers.{h,cpp}): every light with a position gets LightBounds (a box, its
// power, the cone of its normals and how far past that cone it emits); the tree is built by
// pbrt-v4's SAH-like cost and flattened to gpu::LightBvhNode. A light is chosen by descending
// from the root, taking each child in proportion to lightBvhImportance at the shading point;
// lightBvhPmf replays an item's stored trail to get the same probability for MIS.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "shared/light_bvh.h"

namespace penumbra {

// Bounds of the light a tree item stands for (pbrt-v4 LightBounds, lights.h).
struct LightBounds {
    glm::vec3 boundsMin{0.0f};
    glm::vec3 boundsMax{0.0f};
    float power = 0.0f;  // phi
    glm::vec3 axis{0.0f, 0.0f, 1.0f};
    float cosThetaO = 1.0f;  // normals lie within theta_o of axis
    float cosThetaE = 0.0f;  // and light leaves within theta_e past each normal
    bool twoSided = false;
    uint32_t light = 0;        // index into Light[]
    uint32_t primitive = ~0u;  // a mesh light's triangle, else ~0u
};

// Per kind, with power = the mean of RGB emission times pbrt-v4's Phi for that kind.
LightBounds pointLightBounds(glm::vec3 position, float meanIntensity, uint32_t light);
LightBounds spotLightBounds(glm::vec3 position, glm::vec3 axis, float cosInner, float cosOuter, float meanIntensity,
                            uint32_t light);
LightBounds sphereLightBounds(glm::vec3 center, float radius, float meanRadiance, uint32_t light);
// A flat emitter (quad or triangle) of the given area and geometric normal.
LightBounds flatLightBounds(glm::vec3 boundsMin, glm::vec3 boundsMax, glm::vec3 normal, float area, float meanRadiance,
                            bool twoSided, uint32_t light, uint32_t primitive);

struct LightBvh {
    std::vector<gpu::LightBvhNode> nodes;  // empty when no item has power
    std::vector<gpu::LightBvhItem> items;  // indexed by a leaf's item index
    uint32_t infiniteCount = 0;            // directional and environment lights beside the tree
};

// Items with zero power are left out (never chosen, pmf 0), as pbrt-v4 does.
LightBvh buildLightBvh(std::vector<LightBounds> lights, uint32_t infiniteCount);

// Importance of a node at shading point p with shading normal n (n = 0: no surface, e.g.
// a medium): a bound on what its lights can contribute there (pbrt-v4
// CompactLightBounds::Importance).
float lightBvhImportance(const gpu::LightBvhNode& node, glm::vec3 p, glm::vec3 n);
// The same in two steps: what the importance needs of the node (its box's center and
// squared half diagonal, the decoded cone), then the per-point arithmetic. The flat form of
// small trees (render/light_flat.h) hands the first step's result to the kernel.
gpu::LightImportanceTerms lightBvhImportanceTerms(const gpu::LightBvhNode& node);
float lightImportance(const gpu::LightImportanceTerms& terms, glm::vec3 p, glm::vec3 n);

// Probability that the tree is used rather than one of the infinite lights: pbrt-v4 gives
// each infinite light and the tree as a whole the same probability.
float lightBvhTreeProbability(const LightBvh& bvh);

struct LightBvhSample {
    int32_t item = -1;  // -1: nothing chosen (the tree is empty)
    float pmf = 0.0f;
};
// Descends with one uniform number u in [0, 1), rescaled and reused at each level
// (pbrt-v4). The pmf is the tree's own: the caller multiplies by lightBvhTreeProbability.
LightBvhSample sampleLightBvh(const LightBvh& bvh, glm::vec3 p, glm::vec3 n, float u);
// The probability that sampleLightBvh chooses `item` at (p, n), replayed from its trail.
float lightBvhPmf(const LightBvh& bvh, glm::vec3 p, glm::vec3 n, uint32_t item);

}  // namespace penumbra
