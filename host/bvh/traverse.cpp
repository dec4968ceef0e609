// CPU traversal of the flat BVH (closest hit, any hit: one loop, as on the GPU) and the
// brute-force reference. The loop mirrors `traverse` in shaders/geometry/bvh.glsl step by
// step, with the intersection routines of bvh/intersect.h, so CPU and GPU results differ
// only by rounding.
#include "bvh/bvh.h"
#include "bvh/intersect.h"

namespace penumbra {

namespace {

// The loop behind both queries, step for step the `traverse` of shaders/geometry/bvh.glsl,
// over the child pairs (shared/types.h): while-while (descend to a leaf, then test its
// primitives), nearest child first with the far child's entry distance on the stack for
// closest hits, plain order and a return at the first hit for `anyHit`. Returns whether
// anything was hit; `hit` holds the closest hit found (for `anyHit`, the first). `work`
// counts the pairs and primitives tested.
bool traverse(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax, bool anyHit, CpuHit& hit,
              TraversalWork& work) {
    hit.t = tMax;
    hit.primitive = gpu::NO_HIT;
    hit.uv = glm::vec2(0.0f);
    // A NaN or infinite ray misses (see bvh.glsl: it must not enter the loop).
    if (glm::any(glm::isnan(origin)) || glm::any(glm::isinf(origin)) || glm::any(glm::isnan(dir)) ||
        glm::any(glm::isinf(dir)))
        return false;
    glm::vec3 invDir = rayInverseDirection(dir);
    uint32_t stackNode[BVH_MAX_DEPTH];  // offset | primCount << BVH_COUNT_SHIFT
    float stackEntry[BVH_MAX_DEPTH];
    int sp = 0;
    const gpu::BvhNode* pairs = bvh.childPairs.data();
    if (bvh.childPairs.size() < 2) return false;
    uint32_t offset = 0, count = 0;  // an interior node whose children are pair 0: the root
    while (true) {
        // Descend to a leaf, or until both children are missed.
        bool atLeaf = false;
        while (true) {
            if (count > 0) {
                atLeaf = true;
                break;
            }
            ++work.pairs;
            const gpu::BvhNode& c0 = pairs[2 * offset];
            const gpu::BvhNode& c1 = pairs[2 * offset + 1];
            float t0, t1;
            bool hit0 = intersectBox(c0.boundsMin, c0.boundsMax, origin, invDir, hit.t, t0);
            bool hit1 = intersectBox(c1.boundsMin, c1.boundsMax, origin, invDir, hit.t, t1);
            if (!hit0 && !hit1) break;
            if (hit0 && hit1) {
                bool firstNear = anyHit || t0 <= t1;
                const gpu::BvhNode& far = firstNear ? c1 : c0;
                const gpu::BvhNode& near = firstNear ? c0 : c1;
                stackNode[sp] = far.offset | (far.primCount << BVH_COUNT_SHIFT);
                stackEntry[sp] = firstNear ? t1 : t0;
                ++sp;
                offset = near.offset;
                count = near.primCount;
            } else {
                const gpu::BvhNode& c = hit0 ? c0 : c1;
                offset = c.offset;
                count = c.primCount;
            }
        }
        if (atLeaf) {
            for (uint32_t i = offset; i < offset + count; ++i) {
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
        }
        // Pop the next deferred child that can still hold something nearer than the hit.
        bool found = false;
        while (sp > 0) {
            --sp;
            if (anyHit || stackEntry[sp] <= hit.t * gpu::BOX_EXIT_SCALE) {
                offset = stackNode[sp] & gpu::BVH_OFFSET_MASK;
                count = stackNode[sp] >> BVH_COUNT_SHIFT;
                found = true;
                break;
            }
        }
        if (!found) break;
    }
    return hit.primitive != gpu::NO_HIT;
}

}  // namespace

std::optional<CpuHit> intersectClosest(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax,
                                       TraversalWork* work) {
    CpuHit hit;
    TraversalWork counted;
    bool found = traverse(bvh, origin, dir, tMax, false, hit, counted);
    if (work) {
        work->pairs += counted.pairs;
        work->primitives += counted.primitives;
    }
    if (!found) return std::nullopt;
    return hit;
}

bool intersectAny(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax) {
    CpuHit hit;
    TraversalWork work;
    return traverse(bvh, origin, dir, tMax, true, hit, work);
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
