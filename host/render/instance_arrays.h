// Instances traced through a two-level BVH (SCENE_FORMAT.md "instance"): each instanced
// group's shapes become primitives once, in the group's frame, with a tree of their own
// (the bottom level); every instance is one PRIM_INSTANCE primitive of the scene's tree
// (the top level), whose box is the world box of its group's tree moved by its to_world,
// and one gpu::Instance record (its maps both ways, the group's root, its material). The
// groups' wide nodes follow the scene's in Bvh::wideNodes, their primitives follow the
// scene's on the GPU (InstanceArrays::primitives); shaders/geometry/instances.glsl
// traverses them. An instance costs sizeof(gpu::Instance) + sizeof(gpu::Primitive) and
// its share of the top-level nodes, whatever its group holds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bvh/bvh.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace penumbra {

struct InstanceArrays {
    std::vector<gpu::Instance> instances;    // BINDING_INSTANCES, one per Scene::instances
    std::vector<gpu::Primitive> primitives;  // every group's primitives in its leaf order, group after group
};

// The bottom level: a tree over each group's primitives (`groupPrimitives[g]`, in the
// group's frame, as buildSceneArrays flattens shapes), with nothing beside it.
std::vector<Bvh> buildGroupTrees(std::vector<std::vector<gpu::Primitive>> groupPrimitives, const BvhOptions& options);

// One PRIM_INSTANCE primitive per instance, appended to `top` (the scene's own primitives,
// before the top-level build): its box, the world box of its group's tree's box moved by
// its to_world (the eight corners), widened by a few float steps so that rounding of the
// ray's move into the group's frame never culls a hit.
void appendInstancePrimitives(const Scene& scene, const std::vector<Bvh>& groupTrees, std::vector<gpu::Primitive>& top);

// After the top-level build: the groups' wide nodes appended to top.wideNodes, their child
// references moved past the scene's nodes and primitives; the groups' primitives and the
// instance records into `out`.
void placeGroupTrees(const Scene& scene, std::vector<Bvh> groupTrees, Bvh& top, InstanceArrays& out);

// Every primitive the GPU holds: the scene's (leaf order) and then the groups'.
std::vector<gpu::Primitive> allPrimitives(const Bvh& top, const InstanceArrays& instanced);

// NODE_READS_* for a scene with instances: the traversal with a local-array stack, the one
// that geometry/instances.glsl extends (the "_address" kernels' traversal does not know
// instances; they read the nodes 32 bytes at a time, as the "_int64" kernels do).
uint32_t nodeReadsWithInstances(uint32_t nodeReads);

}  // namespace penumbra
