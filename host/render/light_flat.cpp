// The flat form of a small light tree (see light_flat.h).
#include "render/light_flat.h"

#include <cstring>
#include <stdexcept>

namespace penumbra {

bool lightFlatPays(size_t items, bool inlined) { return inlined && items > 0 && items <= LIGHT_FLAT_MAX_LEAVES; }

std::vector<gpu::LightFlatLeaf> lightFlatLeaves(const LightBvh& bvh, const std::vector<uint32_t>& hitPrimitives) {
    if (hitPrimitives.size() != bvh.items.size()) throw std::logic_error("lightFlatLeaves: one hit primitive per item");
    std::vector<gpu::LightFlatLeaf> leaves(bvh.items.size());
    for (const gpu::LightBvhNode& node : bvh.nodes) {
        if (!(node.childOrItem & gpu::LIGHT_BVH_LEAF)) continue;
        const uint32_t item = node.childOrItem & gpu::LIGHT_BVH_INDEX_MASK;
        leaves[item] = {lightBvhImportanceTerms(node), bvh.items[item].light, bvh.items[item].primitive,
                        hitPrimitives[item]};
    }
    return leaves;
}

std::vector<uint32_t> lightFlatWords(const std::vector<gpu::LightFlatLeaf>& leaves) {
    if (leaves.size() > LIGHT_FLAT_MAX_LEAVES)
        throw std::logic_error("lightFlatWords: more than LIGHT_FLAT_MAX_LEAVES");
    std::vector<uint32_t> words(leaves.size() * LIGHT_FLAT_WORDS);
    std::memcpy(words.data(), leaves.data(), words.size() * sizeof(uint32_t));
    return words;
}

std::vector<float> lightFlatWeights(const std::vector<gpu::LightFlatLeaf>& leaves, glm::vec3 p, glm::vec3 n,
                                    float& total) {
    std::vector<float> w(leaves.size());
    total = 0.0f;
    for (size_t k = 0; k < leaves.size(); ++k) total += w[k] = lightImportance(leaves[k].terms, p, n);
    if (!(total > 0.0f)) {
        // Every bound is zero: the powers, so that every leaf keeps a probability (a light
        // chosen where its bound is zero contributes nothing: a wasted sample, never bias).
        total = 0.0f;
        for (size_t k = 0; k < leaves.size(); ++k) total += w[k] = leaves[k].terms.power;
    }
    return w;
}

LightBvhSample sampleLightFlat(const std::vector<gpu::LightFlatLeaf>& leaves, glm::vec3 p, glm::vec3 n, float u) {
    if (leaves.empty()) return {};
    float total;
    const std::vector<float> w = lightFlatWeights(leaves, p, n, total);
    const float target = u * total;
    float below = 0.0f, chosen = 0.0f;
    int32_t leaf = 0;
    bool found = false;
    // The first leaf of positive weight whose running sum passes u * total; the last such
    // leaf where rounding leaves u * total at the total.
    for (size_t k = 0; k < w.size(); ++k) {
        below += w[k];
        if (!found && w[k] > 0.0f) {
            leaf = int32_t(k);
            chosen = w[k];
            found = target < below;
        }
    }
    return {leaf, chosen / total};
}

float lightFlatPmf(const std::vector<gpu::LightFlatLeaf>& leaves, glm::vec3 p, glm::vec3 n, uint32_t leaf) {
    if (leaf >= leaves.size()) return 0.0f;
    float total;
    const std::vector<float> w = lightFlatWeights(leaves, p, n, total);
    return w[leaf] / total;
}

}  // namespace penumbra
