// Inline geometry: the rule and the specialization words (see inline_geometry.h).
#include "render/inline_geometry.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <stdexcept>
#include <string>

#include "bvh/bvh.h"

namespace penumbra {

bool inlineGeometryPays(const SceneArrays& arrays) {
    const size_t n = arrays.bvh.primitives.size();
    return n > 0 && n <= size_t(INLINE_MAX_PRIMITIVES);
}

uint32_t inlineKernelCapacity(uint32_t count) {
    static_assert(INLINE_MAX_PRIMITIVES % INLINE_CAPACITY_STEP == 0);
    if (count == 0 || count > uint32_t(INLINE_MAX_PRIMITIVES))
        throw std::logic_error("inlineKernelCapacity: no inline kernel for " + std::to_string(count) + " primitives");
    return (count + INLINE_CAPACITY_STEP - 1) / INLINE_CAPACITY_STEP * INLINE_CAPACITY_STEP;
}

namespace {

// A set of primitives (leaf-order indices) that will share a group's slots, and their box.
struct Cluster {
    std::vector<uint32_t> members;
    Aabb box;
};

Aabb boundsOf(const gpu::Primitive& p) {
    // The same bounds the BVH's leaves get (bvh/build.cpp), tested by the kernel with the
    // BVH's own box test (intersectBox), so no group holding a hit is ever skipped.
    Aabb b;
    primitiveBounds(p, b.lo, b.hi);
    return b;
}

// The subtrees of the binary tree below `node` that hold at most INLINE_GROUP_SIZE
// primitives, largest first along each path: spatially compact sets, in leaf order.
void collectClusters(const Bvh& bvh, uint32_t node, std::vector<Cluster>& out) {
    struct Range {
        uint32_t begin, end;
    };
    // A subtree's primitives are a contiguous range of leaf order (bvh/build.cpp).
    auto range = [&](auto&& self, uint32_t n) -> Range {
        const gpu::BvhNode& b = bvh.nodes[n];
        if (b.primCount > 0 || bvh.nodes.size() == 1) return {b.offset, b.offset + b.primCount};
        const Range l = self(self, n + 1), r = self(self, b.offset);
        return {std::min(l.begin, r.begin), std::max(l.end, r.end)};
    };
    const Range r = range(range, node);
    const gpu::BvhNode& b = bvh.nodes[node];
    if (r.end - r.begin <= INLINE_GROUP_SIZE || b.primCount > 0) {
        Cluster c;
        for (uint32_t i = r.begin; i < r.end; ++i) {
            c.members.push_back(i);
            c.box.grow(boundsOf(bvh.primitives[i]));
        }
        if (!c.members.empty()) out.push_back(std::move(c));
        return;
    }
    collectClusters(bvh, node + 1, out);
    collectClusters(bvh, b.offset, out);
}

// Clusters merged pairwise (the pair whose joint box has the least area first) until at
// most `maxGroups` remain; false when no two fit one group any more.
bool mergeClusters(std::vector<Cluster>& clusters, size_t maxGroups) {
    while (clusters.size() > maxGroups) {
        size_t bestA = 0, bestB = 0;
        float bestArea = std::numeric_limits<float>::infinity();
        for (size_t a = 0; a < clusters.size(); ++a)
            for (size_t b = a + 1; b < clusters.size(); ++b) {
                if (clusters[a].members.size() + clusters[b].members.size() > INLINE_GROUP_SIZE) continue;
                Aabb joint = clusters[a].box;
                joint.grow(clusters[b].box);
                if (joint.area() < bestArea) {
                    bestArea = joint.area();
                    bestA = a;
                    bestB = b;
                }
            }
        if (bestB == 0) return false;
        Cluster& into = clusters[bestA];
        into.members.insert(into.members.end(), clusters[bestB].members.begin(), clusters[bestB].members.end());
        std::sort(into.members.begin(), into.members.end());
        into.box.grow(clusters[bestB].box);
        clusters.erase(clusters.begin() + std::ptrdiff_t(bestB));
    }
    return true;
}

void pushFloats(std::vector<uint32_t>& words, const glm::vec3& v) {
    for (int k = 0; k < 3; ++k) words.push_back(std::bit_cast<uint32_t>(v[k]));
}

}  // namespace

InlineGeometryWords inlineGeometryWords(const Bvh& bvh) {
    const std::vector<gpu::Primitive>& primitives = bvh.primitives;
    if (primitives.empty() || primitives.size() > size_t(INLINE_MAX_PRIMITIVES))
        throw std::logic_error("inlineGeometryWords: not 1 to INLINE_MAX_PRIMITIVES primitives");
    // Groups: compact subtrees of the BVH, each padded to INLINE_GROUP_SIZE slots, where
    // they fit the kernel's INLINE_MAX_GROUPS groups; otherwise runs of INLINE_GROUP_SIZE
    // consecutive primitives in leaf order (always fits: at most INLINE_MAX_PRIMITIVES).
    // The fewest groups first: the kernel variant's capacity follows the slots in use, and a
    // larger variant takes llvmpipe's front end longer on every start (docs/performance-history/round-08.md).
    std::vector<Cluster> clusters, groups;
    collectClusters(bvh, 0, clusters);
    bool merged = false;
    for (size_t maxGroups = inlineKernelCapacity(uint32_t(primitives.size())) / INLINE_GROUP_SIZE;
         !merged && maxGroups <= size_t(INLINE_MAX_GROUPS); maxGroups += INLINE_CAPACITY_STEP / INLINE_GROUP_SIZE) {
        groups = clusters;
        merged = mergeClusters(groups, maxGroups);
    }
    if (!merged) {
        groups.clear();
        for (uint32_t i = 0; i < primitives.size(); ++i) {
            if (i % INLINE_GROUP_SIZE == 0) groups.emplace_back();
            groups.back().members.push_back(i);
            groups.back().box.grow(boundsOf(primitives[i]));
        }
    }
    // The fullest group last, so that the fewest empty slots are declared.
    std::stable_sort(groups.begin(), groups.end(),
                     [](const Cluster& a, const Cluster& b) { return a.members.size() < b.members.size(); });
    Aabb scene;
    for (const Cluster& g : groups) scene.grow(g.box);

    InlineGeometryWords words;
    for (size_t g = 0; g < groups.size(); ++g) {
        const bool last = g + 1 == groups.size();
        const size_t slots = last ? groups[g].members.size() : size_t(INLINE_GROUP_SIZE);
        for (size_t k = 0; k < slots; ++k) {
            if (k >= groups[g].members.size()) {  // an empty slot: compiled out
                words.slots.push_back(INLINE_SLOT_EMPTY);
                words.slots.insert(words.slots.end(), INLINE_PRIMITIVE_WORDS - 1, 0u);
                continue;
            }
            const uint32_t index = groups[g].members[k];
            const gpu::Primitive& p = primitives[index];
            words.slots.push_back((p.typeAndNormals & gpu::PRIM_TYPE_MASK) | index << INLINE_SLOT_INDEX_SHIFT);
            for (const glm::vec3& v : {p.p0, p.p1, p.p2}) pushFloats(words.slots, v);
        }
        // A box test pays where a SIMD group's rays often all miss the box and it stands for
        // several primitive tests: a box of at least half the scene box's area is hit by
        // most rays, and one box test costs about what one primitive test costs.
        const bool tested = groups[g].members.size() >= kInlineGroupTestedFrom &&
                            groups[g].box.area() < kInlineGroupTestedBelow * scene.area();
        pushFloats(words.groups, groups[g].box.lo);
        pushFloats(words.groups, groups[g].box.hi);
        words.groups.push_back(tested ? 1u : 0u);
    }
    return words;
}

uint32_t InlineGeometryWords::slotCount() const { return uint32_t(slots.size() / INLINE_PRIMITIVE_WORDS); }

}  // namespace penumbra
