// The two-level BVH's arrays (see instance_arrays.h).
#include "render/instance_arrays.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra {

std::vector<Bvh> buildGroupTrees(std::vector<std::vector<gpu::Primitive>> groupPrimitives, const BvhOptions& options) {
    // The group's traversal (instances.glsl, testInstance) walks the tree alone: nothing beside it.
    BvhOptions bottom = options;
    bottom.maxBeside = 0;
    std::vector<Bvh> trees;
    trees.reserve(groupPrimitives.size());
    for (std::vector<gpu::Primitive>& prims : groupPrimitives) trees.push_back(buildBvh(std::move(prims), bottom));
    return trees;
}

void appendInstancePrimitives(const Scene& scene, const std::vector<Bvh>& groupTrees,
                              std::vector<gpu::Primitive>& top) {
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const Aabb box = bvhBounds(groupTrees.at(instance.group));
        glm::dvec3 lo(INFINITY), hi(-INFINITY);
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 p((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                               (corner & 4) ? box.hi.z : box.lo.z);
            const glm::dvec3 q = instance.linear * p + instance.translation;
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        // A few float steps of the box's size and place: the kernel moves the ray, not the
        // box, in float arithmetic.
        const glm::dvec3 pad = 1e-5 * (glm::abs(lo) + glm::abs(hi) + (hi - lo)) + 1e-30;
        gpu::Primitive p{};
        p.p0 = glm::vec3(lo - pad);
        p.p1 = glm::vec3(hi + pad);
        p.p2 = p.p1;
        p.typeAndNormals = gpu::PRIM_INSTANCE | (i << 2);
        p.material = instance.material;
        p.light = gpu::NO_LIGHT;
        top.push_back(p);
    }
}

namespace {

// Row r of the 3x4 map x -> linear x + translation.
glm::vec4 row(const glm::dmat3& linear, const glm::dvec3& translation, int r) {
    return glm::vec4(float(linear[0][r]), float(linear[1][r]), float(linear[2][r]), float(translation[r]));
}

}  // namespace

void placeGroupTrees(const Scene& scene, std::vector<Bvh> groupTrees, Bvh& top, InstanceArrays& out) {
    const uint32_t topPrimitives = uint32_t(top.primitives.size());
    size_t total = topPrimitives;
    for (const Bvh& tree : groupTrees) total += tree.primitives.size();
    if (total > gpu::BVH_MAX_PRIMITIVES)
        throw std::length_error("the scene and its groups have more than " + std::to_string(gpu::BVH_MAX_PRIMITIVES) +
                                " primitives");
    std::vector<uint32_t> roots;
    for (Bvh& tree : groupTrees) {
        const uint32_t nodeBase = uint32_t(top.wideNodes.size());
        const uint32_t primitiveBase = topPrimitives + uint32_t(out.primitives.size());
        roots.push_back(nodeBase);
        for (gpu::WideNode node : tree.wideNodes) {
            for (uint32_t* child : {&node.child0, &node.child1, &node.child2, &node.child3}) {
                // An interior child (no primitive count) names a node, a leaf its first primitive.
                const bool leaf = (*child >> BVH_COUNT_SHIFT) != 0;
                *child += leaf ? primitiveBase : nodeBase;
            }
            top.wideNodes.push_back(node);
        }
        out.primitives.insert(out.primitives.end(), tree.primitives.begin(), tree.primitives.end());
    }
    for (const Instance& instance : scene.instances) {
        gpu::Instance record{};
        const glm::dmat3 inverse = glm::inverse(instance.linear);
        const glm::dvec3 inverseTranslation = -(inverse * instance.translation);
        record.worldToObject0 = row(inverse, inverseTranslation, 0);
        record.worldToObject1 = row(inverse, inverseTranslation, 1);
        record.worldToObject2 = row(inverse, inverseTranslation, 2);
        record.objectToWorld0 = row(instance.linear, instance.translation, 0);
        record.objectToWorld1 = row(instance.linear, instance.translation, 1);
        record.objectToWorld2 = row(instance.linear, instance.translation, 2);
        record.root = roots.at(instance.group);
        record.material = instance.material == kNoMaterialOverride ? gpu::NO_MATERIAL_OVERRIDE : instance.material;
        out.instances.push_back(record);
    }
}

std::vector<gpu::Primitive> allPrimitives(const Bvh& top, const InstanceArrays& instanced) {
    std::vector<gpu::Primitive> all;
    all.reserve(top.primitives.size() + instanced.primitives.size());
    all.insert(all.end(), top.primitives.begin(), top.primitives.end());
    all.insert(all.end(), instanced.primitives.begin(), instanced.primitives.end());
    return all;
}

uint32_t nodeReadsWithInstances(uint32_t nodeReads) {
    return nodeReads == NODE_READS_ADDRESS ? NODE_READS_STORAGE_32 : nodeReads;
}

}  // namespace penumbra
