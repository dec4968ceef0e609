// CPU traversal of the flat BVH (closest hit, any hit: one loop, as on the GPU) and the
// brute-force reference. The loop mirrors `traverse` in shaders/geometry/bvh.glsl step by
// step, with the intersection routines of bvh/intersect.h, so CPU and GPU results differ
// only by rounding.
#include <algorithm>

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

// The loop behind both queries, step for step the `traverse` of shaders/geometry/bvh.glsl,
// over the wide nodes (shared/types.h): while-while (descend to a leaf, then test its
// primitives), nearest child first, a node with other children hit back on the stack with
// their bits, tested again when popped; a return at the first hit for `anyHit`. Returns
// whether anything was hit; `hit` holds the closest hit found (for `anyHit`, the first).
// `work` counts the nodes and primitives tested and the deepest the stack went.
bool traverse(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax, bool anyHit, CpuHit& hit,
              TraversalWork& work) {
    hit.t = tMax;
    hit.primitive = gpu::NO_HIT;
    hit.uv = glm::vec2(0.0f);
    // A NaN or infinite ray misses (see bvh.glsl: it must not enter the loop).
    if (glm::any(glm::isnan(origin)) || glm::any(glm::isinf(origin)) || glm::any(glm::isnan(dir)) ||
        glm::any(glm::isinf(dir)))
        return false;
    if (bvh.wideNodes.empty()) return false;
    glm::vec3 invDir = rayInverseDirection(dir);
    uint32_t stack[BVH_MAX_DEPTH];  // node | children still to visit << WIDE_STACK_MASK_SHIFT
    int sp = 0;
    uint32_t node = 0, allowed = gpu::WIDE_ALL_CHILDREN;  // the root, every child
    while (true) {
        // Descend to a leaf, or until no allowed child is hit.
        bool atLeaf = false;
        uint32_t leaf = 0;
        const uint32_t nodesBefore = work.nodes, primitivesBefore = work.primitives;
        const auto endRound = [&] {
            if (work.rounds)
                work.rounds->push_back((work.nodes - nodesBefore) << 16 | (work.primitives - primitivesBefore));
        };
        while (true) {
            ++work.nodes;
            const gpu::WideNode& wide = bvh.wideNodes[node];
            uint32_t hits = 0, refs[WIDE_NODE_ARITY];
            float tEntry[WIDE_NODE_ARITY];
            for (uint32_t c = 0; c < WIDE_NODE_ARITY; ++c) {
                WideChildBox box = decodeWideChild(wide, c);
                refs[c] = box.ref;
                if (intersectBox(box.lo, box.hi, origin, invDir, hit.t, tEntry[c]) && box.exists) hits |= 1u << c;
            }
            hits &= allowed;
            if (hits == 0) break;
            uint32_t c = nearestChild(hits, tEntry);
            uint32_t rest = hits & ~(1u << c);
            if (rest != 0) {
                stack[sp++] = node | (rest << gpu::WIDE_STACK_MASK_SHIFT);
                work.deepestStack = std::max(work.deepestStack, uint32_t(sp));
            }
            uint32_t next = refs[c];
            if ((next >> BVH_COUNT_SHIFT) != 0) {
                atLeaf = true;
                leaf = next;
                break;
            }
            node = next;
            allowed = gpu::WIDE_ALL_CHILDREN;
        }
        if (atLeaf) {
            uint32_t first = leaf & gpu::BVH_OFFSET_MASK, end = first + (leaf >> BVH_COUNT_SHIFT);
            for (uint32_t i = first; i < end; ++i) {
                float t;
                glm::vec2 uv;
                ++work.primitives;
                if (intersectPrimitive(bvh.primitives[i], origin, dir, hit.t, t, uv)) {
                    hit.t = t;
                    hit.primitive = i;
                    hit.uv = uv;
                    if (anyHit) {
                        endRound();
                        return true;
                    }
                }
            }
        }
        endRound();
        if (sp == 0) break;
        --sp;
        node = stack[sp] & gpu::WIDE_STACK_NODE_MASK;
        allowed = stack[sp] >> gpu::WIDE_STACK_MASK_SHIFT;
    }
    return hit.primitive != gpu::NO_HIT;
}

// traverse, its work added to `work` when that is given (and its rounds recorded where
// `work` asks for them).
bool traverseCounting(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax, bool anyHit, CpuHit& hit,
                      TraversalWork* work) {
    TraversalWork counted;
    counted.rounds = work ? work->rounds : nullptr;
    const bool found = traverse(bvh, origin, dir, tMax, anyHit, hit, counted);
    if (work) {
        work->nodes += counted.nodes;
        work->primitives += counted.primitives;
        work->deepestStack = std::max(work->deepestStack, counted.deepestStack);
    }
    return found;
}

}  // namespace

std::optional<CpuHit> intersectClosest(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax,
                                       TraversalWork* work) {
    CpuHit hit;
    if (!traverseCounting(bvh, origin, dir, tMax, false, hit, work)) return std::nullopt;
    return hit;
}

bool intersectAny(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax, TraversalWork* work) {
    CpuHit hit;
    return traverseCounting(bvh, origin, dir, tMax, true, hit, work);
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
