// The GPU structs of shaders/shared/types.h have the std430 sizes and offsets the GLSL
// side assumes (a vec3 followed by one scalar packs into 16 bytes).
#include <cstddef>

#include <gtest/gtest.h>

#include "shared/types.h"

using namespace penumbra::gpu;

static_assert(sizeof(AccumSum) == 16 && offsetof(AccumSum, count) == 12 && sizeof(AccumCompensation) == 16 &&
              offsetof(AccumCompensation, unused) == 12);
static_assert(sizeof(BvhNode) == 32 && offsetof(BvhNode, offset) == 12 && offsetof(BvhNode, boundsMax) == 16 &&
              offsetof(BvhNode, primCount) == 28);
static_assert(sizeof(Primitive) == 48 && offsetof(Primitive, typeAndNormals) == 12 &&
              offsetof(Primitive, p1) == 16 && offsetof(Primitive, material) == 28 && offsetof(Primitive, p2) == 32 &&
              offsetof(Primitive, light) == 44);
static_assert(sizeof(TriangleNormals) == 48);
static_assert(sizeof(Instance) == 112 && offsetof(Instance, objectToWorld0) == 48 && offsetof(Instance, root) == 96 &&
              offsetof(Instance, material) == 100);
static_assert(sizeof(Material) == 32 && offsetof(Material, type) == 12 && offsetof(Material, ks) == 16 &&
              offsetof(Material, exponent) == 28);
static_assert(sizeof(Light) == 48 && offsetof(Light, emission) == 16 && offsetof(Light, area) == 28 &&
              offsetof(Light, position) == 32 && offsetof(Light, selectionProb) == 44);
static_assert(sizeof(AliasEntry) == 16);
static_assert(sizeof(RenderParams) % 16 == 0 && offsetof(RenderParams, right) == 16 &&
              offsetof(RenderParams, up) == 32 && offsetof(RenderParams, width) == 44 &&
              offsetof(RenderParams, forward) == 48 && offsetof(RenderParams, height) == 60 &&
              offsetof(RenderParams, seed) == 64 && offsetof(RenderParams, lightBvhTableOffset) == 120 &&
              sizeof(RenderParams) == 144);
static_assert(sizeof(PassConstants) == 52 && offsetof(PassConstants, nodeAddressLow) == 20 &&
              offsetof(PassConstants, stackAddressLow) == 28 && offsetof(PassConstants, stackDepth) == 36 &&
              offsetof(PassConstants, queueTiles) == 40 && offsetof(PassConstants, tileColumns) == 44 &&
              offsetof(PassConstants, loopProbeTrips) == 48);
// Texel-buffer views (RGBA32UI, 16 bytes a texel) cover the structs exactly: a wide node,
// a primitive and a material are whole numbers of texels.
static_assert(sizeof(WideNode) == WIDE_NODE_TEXELS * 16 && offsetof(WideNode, meta) == 12 &&
              offsetof(WideNode, loX) == 16 && offsetof(WideNode, hiY) == 32 && offsetof(WideNode, child0) == 40 &&
              offsetof(WideNode, child2) == 48 && sizeof(Primitive) == PRIMITIVE_TEXELS * 16 &&
              sizeof(Material) == MATERIAL_TEXELS * 16);
static_assert(sizeof(TextureRef) == TEXTURE_REF_TEXELS * 16 && offsetof(TextureRef, firstTexel) == 16 &&
              sizeof(TextureTransform) == TEXTURE_TRANSFORM_TEXELS * 16 && offsetof(TextureTransform, v) == 16);
// A wide node's child packs offset | primCount << BVH_COUNT_SHIFT into 32 bits; a stack
// entry packs a node index (below BVH_MAX_PRIMITIVES) and a child mask.
static_assert(BVH_COUNT_SHIFT <= WIDE_STACK_MASK_SHIFT && WIDE_NODE_ARITY + WIDE_STACK_MASK_SHIFT <= 32u &&
              WIDE_NODE_ARITY + WIDE_CHILD_MASK_SHIFT <= 32u);
static_assert(BVH_MAX_LEAF_SIZE < (1u << (32u - BVH_COUNT_SHIFT)) && BVH_MAX_PRIMITIVES - 1u == BVH_OFFSET_MASK);

TEST(Layout, StructSizesMatchStd430) {
    // The static_asserts above are the test; this records the sizes in the test log.
    EXPECT_EQ(sizeof(BvhNode), 32u);
    EXPECT_EQ(sizeof(Primitive), 48u);
    EXPECT_EQ(sizeof(Light), 48u);
    EXPECT_EQ(sizeof(RenderParams) % 16, 0u);
}
