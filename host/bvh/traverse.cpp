// CPU traversal of the flat BVH (closest hit, any hit: one loop, as on the GPU, with either
// kind of stack entry) and the brute-force reference. The loop mirrors `traverse` in
// shaders/geometry/bvh.glsl step by step, with the intersection routines of
// bvh/intersect.h, so CPU and GPU results differ only by rounding.
#include <algorithm>
#include <bit>
#include <utility>

#include "bvh/bvh.h"
#include "bvh/intersect.h"

namespace penumbra {

namespace {

// Of the children in `hits` (not empty), the one the ray enters first; ties go to the lower
// index: nearestChild of bvh.glsl.
uint32_t nearestChild(uint32_t hits, const float tEntry[WIDE_NODE_ARITY]) {
    uint32_t nearest = 0;
    float best = 0.0f;
    bool found = false;
    for (uint32_t c = 0; c < WIDE_NODE_ARITY; ++c) {
        if ((hits & (1u << c)) != 0 && (!found || tEntry[c] < best)) {
            nearest = c;
            best = tEntry[c];
            found = true;
        }
    }
    return nearest;
}

// Orders two children by key (entry distance bits), carrying their references:
// orderChildren of bvh.glsl.
void orderChildren(uint32_t& keyA, uint32_t& refA, uint32_t& keyB, uint32_t& refB) {
    if (keyB < keyA) {
        std::swap(keyA, keyB);
        std::swap(refA, refB);
    }
}

// The four children of a wide node tested against the ray: bit c of the result is set where
// child c exists and is hit before tMax (intersectWideNode of bvh.glsl).
uint32_t testWideNode(const gpu::WideNode& wide, glm::vec3 origin, glm::vec3 invDir, float tMax,
                      float tEntry[WIDE_NODE_ARITY], uint32_t refs[WIDE_NODE_ARITY]) {
    uint32_t hits = 0;
    for (uint32_t c = 0; c < WIDE_NODE_ARITY; ++c) {
        WideChildBox box = decodeWideChild(wide, c);
        refs[c] = box.ref;
        if (intersectBox(box.lo, box.hi, origin, invDir, tMax, tEntry[c]) && box.exists) hits |= 1u << c;
    }
    return hits;
}

// Primitives [first, end) tested against the ray (testPrimitives of bvh.glsl); true when
// `anyHit` and one is hit.
bool testPrimitives(const Bvh& bvh, uint32_t first, uint32_t end, glm::vec3 origin, glm::vec3 dir, bool anyHit,
                    CpuHit& hit, TraversalWork& work) {
    for (uint32_t i = first; i < end; ++i) {
        float t;
        glm::vec2 uv;
        ++work.primitives;
        if (intersectPrimitive(bvh.primitives[i], origin, dir, hit.t, t, uv)) {
            hit.t = t;
            hit.primitive = i;
            hit.uv = uv;
            if (anyHit) return true;
        }
    }
    return false;
}

// The primitives of leaf `leaf` (testLeaf of bvh.glsl).
bool testLeaf(const Bvh& bvh, uint32_t leaf, glm::vec3 origin, glm::vec3 dir, bool anyHit, CpuHit& hit,
              TraversalWork& work) {
    const uint32_t first = leaf & gpu::BVH_OFFSET_MASK;
    return testPrimitives(bvh, first, first + (leaf >> BVH_COUNT_SHIFT), origin, dir, anyHit, hit, work);
}

// The loop behind both queries, step for step the `traverse` of shaders/geometry/bvh.glsl,
// over the wide nodes (shared/types.h): while-while (descend to a leaf, then test its
// primitives), nearest child first, and the other children hit kept on the stack as
// `entries` says: as references, sorted by entry distance; or as their node with their bits,
// tested again when popped. A return at the first hit for `anyHit`. Returns whether
// anything was hit; `hit` holds the closest hit found (for `anyHit`, the first). `work`
// counts the nodes and primitives tested and the deepest the stack went.
bool traverse(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax, bool anyHit, StackEntries entries,
              CpuHit& hit, TraversalWork& work) {
    hit.t = tMax;
    hit.primitive = gpu::NO_HIT;
    hit.uv = glm::vec2(0.0f);
    // A NaN or infinite ray misses (see bvh.glsl: it must not enter the loop).
    if (glm::any(glm::isnan(origin)) || glm::any(glm::isinf(origin)) || glm::any(glm::isnan(dir)) ||
        glm::any(glm::isinf(dir)))
        return false;
    // The primitives beside the tree first (Bvh::besideCount), in order, as bvh.glsl tests
    // them; one round of their own for the lane replay (every lane runs it).
    if (bvh.besideCount > 0) {
        const uint32_t primitivesBefore = work.primitives;
        const bool found =
            testPrimitives(bvh, bvh.besideFirst(), uint32_t(bvh.primitives.size()), origin, dir, anyHit, hit, work);
        if (work.rounds) work.rounds->push_back(work.primitives - primitivesBefore);
        if (found) return true;
    }
    if (bvh.wideNodes.empty()) return hit.primitive != gpu::NO_HIT;
    glm::vec3 invDir = rayInverseDirection(dir);
    // Children: up to WIDE_NODE_ARITY - 1 references per level; nodes: one entry per level.
    uint32_t stack[(WIDE_NODE_ARITY - 1) * BVH_MAX_DEPTH];
    int sp = 0;
    const auto push = [&](uint32_t entry) {
        stack[sp++] = entry;
        work.deepestStack = std::max(work.deepestStack, uint32_t(sp));
    };
    // Children: the reference to take up next. Nodes: the node and its children allowed.
    uint32_t ref = 0, allowed = gpu::WIDE_ALL_CHILDREN;  // the root, every child
    while (true) {
        // Descend to a leaf, or until a node has no (allowed) child hit.
        bool atLeaf = true;  // unless a node has no child hit
        const uint32_t nodesBefore = work.nodes, primitivesBefore = work.primitives;
        const auto endRound = [&] {
            if (work.rounds)
                work.rounds->push_back((work.nodes - nodesBefore) << 16 | (work.primitives - primitivesBefore));
        };
        while ((ref >> BVH_COUNT_SHIFT) == 0) {
            ++work.nodes;
            uint32_t refs[WIDE_NODE_ARITY];
            float tEntry[WIDE_NODE_ARITY];
            const uint32_t hits = testWideNode(bvh.wideNodes[ref], origin, invDir, hit.t, tEntry, refs) & allowed;
            if (hits == 0) {
                atLeaf = false;
                break;
            }
            if (entries == StackEntries::Children) {
                uint32_t key[WIDE_NODE_ARITY];
                for (uint32_t c = 0; c < WIDE_NODE_ARITY; ++c)
                    key[c] = (hits & (1u << c)) != 0 ? std::bit_cast<uint32_t>(tEntry[c]) : 0xffffffffu;
                orderChildren(key[0], refs[0], key[1], refs[1]);
                orderChildren(key[2], refs[2], key[3], refs[3]);
                orderChildren(key[0], refs[0], key[2], refs[2]);
                orderChildren(key[1], refs[1], key[3], refs[3]);
                orderChildren(key[1], refs[1], key[2], refs[2]);
                for (int c = std::popcount(hits) - 1; c >= 1; --c) push(refs[c]);
                ref = refs[0];
            } else {
                const uint32_t c = nearestChild(hits, tEntry);
                const uint32_t rest = hits & ~(1u << c);
                if (rest != 0) push(ref | (rest << gpu::WIDE_STACK_MASK_SHIFT));
                ref = refs[c];
                allowed = gpu::WIDE_ALL_CHILDREN;
            }
        }
        if (atLeaf && testLeaf(bvh, ref, origin, dir, anyHit, hit, work)) {
            endRound();
            return true;
        }
        endRound();
        if (sp == 0) break;
        --sp;
        if (entries == StackEntries::Children) {
            ref = stack[sp];
        } else {
            ref = stack[sp] & gpu::WIDE_STACK_NODE_MASK;
            allowed = stack[sp] >> gpu::WIDE_STACK_MASK_SHIFT;
        }
    }
    return hit.primitive != gpu::NO_HIT;
}

// traverse, its work added to `work` when that is given (and its rounds recorded where
// `work` asks for them).
bool traverseCounting(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax, bool anyHit, StackEntries entries,
                      CpuHit& hit, TraversalWork* work) {
    TraversalWork counted;
    counted.rounds = work ? work->rounds : nullptr;
    const bool found = traverse(bvh, origin, dir, tMax, anyHit, entries, hit, counted);
    if (work) {
        work->nodes += counted.nodes;
        work->primitives += counted.primitives;
        work->deepestStack = std::max(work->deepestStack, counted.deepestStack);
    }
    return found;
}

}  // namespace

std::optional<CpuHit> intersectClosest(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax, TraversalWork* work,
                                       StackEntries entries) {
    CpuHit hit;
    if (!traverseCounting(bvh, origin, dir, tMax, false, entries, hit, work)) return std::nullopt;
    return hit;
}

bool intersectAny(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax, TraversalWork* work,
                  StackEntries entries) {
    CpuHit hit;
    return traverseCounting(bvh, origin, dir, tMax, true, entries, hit, work);
}

std::optional<CpuHit> intersectBruteForce(const std::vector<gpu::Primitive>& primitives, glm::vec3 origin,
                                          glm::vec3 dir, float tMax) {
    CpuHit hit;
    hit.t = tMax;
    hit.primitive = gpu::NO_HIT;
    for (uint32_t i = 0; i < primitives.size(); ++i) {
        float t;
        glm::vec2 uv;
        if (intersectPrimitive(primitives[i], origin, dir, hit.t, t, uv)) {
            hit.t = t;
            hit.primitive = i;
            hit.uv = uv;
        }
    }
    if (hit.primitive == gpu::NO_HIT) return std::nullopt;
    return hit;
}

}  // namespace penumbra
