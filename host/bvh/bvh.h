// Bounding volume hierarchy over the primitives (triangles, spheres, quads in one tree, and
// a few large ones or lone lights beside it: Bvh::besideCount): binned SAH build,
// depth-first flattening for the GPU (shaders/geometry/bvh.glsl), and a CPU traversal of the
// same flat nodes used by tests and tools.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "shared/types.h"

namespace penumbra {

// An axis-aligned box; empty (inverted) until grown.
struct Aabb {
    glm::vec3 lo{std::numeric_limits<float>::max()};
    glm::vec3 hi{-std::numeric_limits<float>::max()};

    void grow(glm::vec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void grow(const Aabb& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    // Surface area; 0 for an empty (inverted) box.
    float area() const {
        glm::vec3 d = hi - lo;
        if (d.x < 0.0f || d.y < 0.0f || d.z < 0.0f) return 0.0f;
        return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
};

struct BvhOptions {
    uint32_t maxLeafSize = 4;  // primitives per leaf at most (fewer when SAH says so)
    // SAH bins per axis at nodes of at least that many primitives; smaller nodes get one per
    // primitive, at least 16 (docs/performance-history/round-15.md: 64 against 16).
    uint32_t binCount = 64;
    // Primitives beside the tree (Bvh::besideCount): at most maxBeside, and only in scenes of
    // at least besideFrom primitives, where the tree is deep enough for them to cost it
    // rounds (smaller scenes go inline or into a shallow tree: render/inline_geometry.h).
    uint32_t maxBeside = 4;
    size_t besideFrom = 64;
};

// A primitive goes beside the tree when its box has at least this share of the surface area
// of the scene's box (most rays enter its box, so the tree saves them nothing), or when it
// is a light by itself (its light's shadow rays all end on it). docs/performance-history/round-22.md.
constexpr float kBesideAreaShare = 0.25f;

struct Bvh {
    std::vector<gpu::BvhNode> nodes;          // binary, depth-first; nodes[0] is the root
    std::vector<gpu::WideNode> wideNodes;     // the same tree, four-wide and quantized: what traversal reads
    std::vector<gpu::Primitive> primitives;   // reordered so every leaf is a contiguous range
    std::vector<uint32_t> originalIndex;      // primitives[i] was input primitive originalIndex[i]
    float sahCost = 0.0f;                     // SAH cost of the tree (traversal 1, intersection 1)
    // The last besideCount primitives are in no leaf: every query tests them, in order,
    // before it walks the tree (shaders/geometry/bvh.glsl and traverse.cpp). A floor that
    // fills the scene's box sat in a leaf beside the root that most rays still tested, one
    // round of the traversal loop each, and took a level of the tree from the rest; beside
    // it, it is one primitive test (BvhOptions, kBesideAreaShare: which go there).
    uint32_t besideCount = 0;
    uint32_t besideFirst() const { return uint32_t(primitives.size()) - besideCount; }
};

// Builds the tree; `primitives` may be empty (one empty leaf that nothing hits). Leaves hold
// at most min(maxLeafSize, BVH_MAX_LEAF_SIZE) primitives; more than BVH_MAX_PRIMITIVES
// primitives throw std::length_error. The primitives that BvhOptions and kBesideAreaShare
// put beside the tree follow the leaves' (Bvh::besideCount).
Bvh buildBvh(std::vector<gpu::Primitive> primitives, const BvhOptions& options = {});

// The box of all of the BVH's primitives, the tree's and those beside it; empty (inverted)
// when there are none.
Aabb bvhBounds(const Bvh& bvh);

struct CpuHit {
    float t = 0.0f;
    uint32_t primitive = 0;  // index into Bvh::primitives (leaf order)
    glm::vec2 uv{0.0f};      // triangle: barycentrics of v1, v2; quad: (s, t); sphere: unused
};

// What a traversal's stack holds (shaders/geometry/bvh.glsl, traverse): child references,
// as the "_address" kernels push them (the children hit, sorted by entry distance, all but
// the nearest), or nodes with the bits of their children still to visit, as the kernels
// with a local-array stack push them (tested again when popped).
enum class StackEntries { Children, Nodes };

// What one traversal did: wide nodes whose boxes it tested, primitives it tested.
struct TraversalWork {
    uint32_t nodes = 0;
    uint32_t primitives = 0;
    // The most entries the traversal stack held: at most childStackDepth with
    // StackEntries::Children, wideStackDepth with StackEntries::Nodes.
    uint32_t deepestStack = 0;
    // When set, one entry per round of the traversal's outer loop: the nodes its descent
    // tested, << 16, | the primitives its leaf tested (penumbra_bench --lanes replays the
    // rounds of eight rays in lockstep, as a SIMD group runs them).
    std::vector<uint32_t>* rounds = nullptr;
};

// Closest hit with t in (0, tMax), and whether any hit exists; the same formulas as the GLSL,
// the same steps as its traversal with `entries` on its stack. `work`, when given, gets the
// traversal's steps added to it.
std::optional<CpuHit> intersectClosest(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax,
                                       TraversalWork* work = nullptr, StackEntries entries = StackEntries::Children);
bool intersectAny(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax, TraversalWork* work = nullptr,
                  StackEntries entries = StackEntries::Children);
// Every primitive tested in turn: the reference the BVH must agree with.
std::optional<CpuHit> intersectBruteForce(const std::vector<gpu::Primitive>& primitives, glm::vec3 origin,
                                          glm::vec3 dir, float tMax);
// Surface area of a node's box; 0 for an empty (inverted) box.
float nodeArea(const gpu::BvhNode& node);

// Bounds of one primitive.
void primitiveBounds(const gpu::Primitive& primitive, glm::vec3& lo, glm::vec3& hi);

// How makeWideNodes picks each wide node's children among the binary nodes below it
// (host/bvh/wide.cpp): the least total surface area of the wide nodes, or the greedy rule
// that opens the largest child first (kept for comparison: tests, benchmarks).
enum class WideCollapse { Optimal, Greedy };

// The four-wide, quantized arrangement of a depth-first binary tree (shared/types.h,
// host/bvh/wide.cpp): wide node 0 is the root, each node's interior children follow in
// depth-first order.
std::vector<gpu::WideNode> makeWideNodes(const std::vector<gpu::BvhNode>& nodes,
                                         WideCollapse rule = WideCollapse::Optimal);
// The total surface area of the binary nodes that makeWideNodes(nodes, rule) turns into wide
// nodes: what the optimal rule minimises (the SAH cost of the node steps).
double wideNodeArea(const std::vector<gpu::BvhNode>& nodes, WideCollapse rule);

// The most entries a traversal of the wide tree `nodes` (makeWideNodes) holds on its stack:
// one per interior node on its path from the root, so the interior nodes on the longest
// such path; at least 1 (also for an empty tree): the kernels whose stack entries are nodes
// hold at most this many. Throws std::logic_error if a child reference
// does not point past its parent, as makeWideNodes lays them out.
uint32_t wideStackDepth(const std::vector<gpu::WideNode>& nodes);
// The most entries a traversal that pushes child references holds (StackEntries::Children):
// up to WIDE_NODE_ARITY - 1 per interior node on its path, so that many times
// wideStackDepth. The "_address" kernels keep this many per invocation.
uint32_t childStackDepth(const std::vector<gpu::WideNode>& nodes);

// Child `child` (0 to 3) of a wide node, decoded as the shader decodes it.
struct WideChildBox {
    glm::vec3 lo{0.0f}, hi{0.0f};
    uint32_t ref = 0;     // offset | primCount << BVH_COUNT_SHIFT
    bool exists = false;  // the node's meta bit for this child
};
WideChildBox decodeWideChild(const gpu::WideNode& node, uint32_t child);

// Depth of the deepest leaf (root = 0); the builder keeps it <= BVH_MAX_DEPTH, the size of
// the traversal stacks on both sides.
uint32_t bvhDepth(const Bvh& bvh);

}  // namespace penumbra
