// CPU traversal of the flat BVH (closest hit, any hit) and the brute-force reference. The
// loop mirrors traceClosest / traceAny in shaders/geometry/bvh.glsl step by step, with the
// intersection routines of bvh/intersect.h, so CPU and GPU results differ only by rounding.
#include "bvh/bvh.h"
#include "bvh/intersect.h"

namespace penumbra {

std::optional<CpuHit> intersectClosest(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax) {
    CpuHit hit;
    hit.t = tMax;
    hit.primitive = gpu::NO_HIT;
    glm::vec3 invDir = rayInverseDirection(dir);
    uint32_t stackNode[BVH_MAX_DEPTH];
    float stackEntry[BVH_MAX_DEPTH];
    int sp = 0;
    float tEntry;
    const gpu::BvhNode* nodes = bvh.nodes.data();
    if (bvh.nodes.empty() || !intersectBox(nodes[0].boundsMin, nodes[0].boundsMax, origin, invDir, tMax, tEntry))
        return std::nullopt;
    uint32_t index = 0;
    while (true) {
        const gpu::BvhNode& node = nodes[index];
        if (node.primCount > 0) {
            for (uint32_t i = node.offset; i < node.offset + node.primCount; ++i) {
                float t;
                glm::vec2 uv;
                if (intersectPrimitive(bvh.primitives[i], origin, dir, hit.t, t, uv)) {
                    hit.t = t;
                    hit.primitive = i;
                    hit.uv = uv;
                }
            }
        } else {
            // Nearest child first; the far one waits on the stack with its entry distance.
            uint32_t left = index + 1, right = node.offset;
            float tLeft, tRight;
            bool hitLeft = intersectBox(nodes[left].boundsMin, nodes[left].boundsMax, origin, invDir, hit.t, tLeft);
            bool hitRight =
                intersectBox(nodes[right].boundsMin, nodes[right].boundsMax, origin, invDir, hit.t, tRight);
            if (hitLeft && hitRight) {
                bool leftFirst = tLeft <= tRight;
                stackNode[sp] = leftFirst ? right : left;
                stackEntry[sp] = leftFirst ? tRight : tLeft;
                ++sp;
                index = leftFirst ? left : right;
                continue;
            }
            if (hitLeft || hitRight) {
                index = hitLeft ? left : right;
                continue;
            }
        }
        // Pop the next deferred node that can still hold something nearer than the hit.
        bool found = false;
        while (sp > 0) {
            --sp;
            if (stackEntry[sp] <= hit.t * kBoxExitScale) {
                index = stackNode[sp];
                found = true;
                break;
            }
        }
        if (!found) break;
    }
    if (hit.primitive == gpu::NO_HIT) return std::nullopt;
    return hit;
}

bool intersectAny(const Bvh& bvh, glm::vec3 origin, glm::vec3 dir, float tMax) {
    glm::vec3 invDir = rayInverseDirection(dir);
    uint32_t stackNode[BVH_MAX_DEPTH];
    int sp = 0;
    float tEntry;
    const gpu::BvhNode* nodes = bvh.nodes.data();
    if (bvh.nodes.empty() || !intersectBox(nodes[0].boundsMin, nodes[0].boundsMax, origin, invDir, tMax, tEntry))
        return false;
    uint32_t index = 0;
    while (true) {
        const gpu::BvhNode& node = nodes[index];
        if (node.primCount > 0) {
            for (uint32_t i = node.offset; i < node.offset + node.primCount; ++i) {
                float t;
                glm::vec2 uv;
                if (intersectPrimitive(bvh.primitives[i], origin, dir, tMax, t, uv)) return true;
            }
        } else {
            uint32_t left = index + 1, right = node.offset;
            float tLeft, tRight;
            bool hitLeft = intersectBox(nodes[left].boundsMin, nodes[left].boundsMax, origin, invDir, tMax, tLeft);
            bool hitRight = intersectBox(nodes[right].boundsMin, nodes[right].boundsMax, origin, invDir, tMax, tRight);
            if (hitLeft && hitRight) stackNode[sp++] = right;
            if (hitLeft || hitRight) {
                index = hitLeft ? left : right;
                continue;
            }
        }
        if (sp == 0) break;
        index = stackNode[--sp];
    }
    return false;
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
