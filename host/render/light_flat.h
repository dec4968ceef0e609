// The flat form of a small light tree (`light_selection: "bvh"`; shaders/lights/light_flat.glsl):
// for a tree of at most LIGHT_FLAT_MAX_LEAVES leaves in a kernel whose geometry is inline
// (render/inline_geometry.h), the kernel gets each leaf's importance terms as specialization
// constants and chooses a leaf from the CDF over all leaves' importances at the shading
// point, instead of descending the tree through texel fetches. Why: on a scene of four
// sphere lights the descent cost 1.73x `power`'s render time, most of it in the node reads
// (each a call on lavapipe) and the per-node decoding (docs/performance-history/many-lights.md,
// "Four lights"); here nothing is read and only the per-point arithmetic remains.
//
// The distribution is a leaf's importance over the sum of all leaves' (the powers where all
// importances are zero, as the descent's childWeights does), a different but as exact a
// distribution as the descent's: sampled and replayed probabilities are the same
// expressions. This file is the host's mirror of the kernel's form, which tests compare
// against, and the rule and words that turn it on.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "render/light_bvh.h"
#include "shared/light_flat.h"

namespace penumbra {

// Whether a tree of `items` items gets the flat form in a kernel with inline geometry
// (`inlined`): 1 to LIGHT_FLAT_MAX_LEAVES items.
bool lightFlatPays(size_t items, bool inlined);

// The tree's leaves in item order: leaf i stands for bvh.items[i], its terms those of its
// node (lightBvhImportanceTerms), its hitPrimitive hitPrimitives[i] (NO_HIT: no BRDF-sampled
// ray can hit it). Empty for an empty tree.
std::vector<gpu::LightFlatLeaf> lightFlatLeaves(const LightBvh& bvh, const std::vector<uint32_t>& hitPrimitives);

// The specialization words of the leaves (SPEC_LIGHT_FLAT_FIRST onwards, LIGHT_FLAT_WORDS
// per leaf): at most LIGHT_FLAT_MAX_LEAVES leaves.
std::vector<uint32_t> lightFlatWords(const std::vector<gpu::LightFlatLeaf>& leaves);

// As the kernel's lightFlatWeights, sampleLightFlat and lightFlatPmf: every leaf's weight at
// (p, n) (importance, or power where all importances are 0) and their sum in `total`; a leaf
// chosen with u in [0, 1) and its pmf; the pmf of leaf `leaf`.
std::vector<float> lightFlatWeights(const std::vector<gpu::LightFlatLeaf>& leaves, glm::vec3 p, glm::vec3 n,
                                    float& total);
LightBvhSample sampleLightFlat(const std::vector<gpu::LightFlatLeaf>& leaves, glm::vec3 p, glm::vec3 n, float u);
float lightFlatPmf(const std::vector<gpu::LightFlatLeaf>& leaves, glm::vec3 p, glm::vec3 n, uint32_t leaf);

}  // namespace penumbra
