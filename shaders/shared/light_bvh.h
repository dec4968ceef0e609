// GPU layout of the light BVH (`light_selection: "bvh"`), shared by the C++ host
// (render/light_bvh.h builds it) and GLSL. Follows pbrt-v4's LightBVHNode and
// CompactLightBounds (src/pbrt/lightsamplers.h, lights.h): nodes are stored depth first, so
// an interior node's first child is the next node and only the second child's index is
// kept. Bounds and the cone axis stay full floats (a quantized box or axis would no longer
// bound its lights); the two cosines are quantized downwards to 16 bits, which only widens
// the cones, as pbrt-v4's QuantizeCos does. std430: every vec3 is followed by a scalar.
#ifndef PENUMBRA_SHARED_LIGHT_BVH_H
#define PENUMBRA_SHARED_LIGHT_BVH_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace penumbra::gpu {
#define PENUMBRA_LB_VEC3 glm::vec3
#define PENUMBRA_LB_UINT std::uint32_t
#define PENUMBRA_LB_CONST inline constexpr
#else
#define PENUMBRA_LB_VEC3 vec3
#define PENUMBRA_LB_UINT uint
#define PENUMBRA_LB_CONST const
#endif

// childOrItem: bit 31 set for a leaf, whose low bits index LightBvhItem[]; otherwise the
// index of the second child. Bit 30: the lights below emit on both sides of their cone.
PENUMBRA_LB_CONST PENUMBRA_LB_UINT LIGHT_BVH_LEAF = 0x80000000u;
PENUMBRA_LB_CONST PENUMBRA_LB_UINT LIGHT_BVH_TWO_SIDED = 0x40000000u;
PENUMBRA_LB_CONST PENUMBRA_LB_UINT LIGHT_BVH_INDEX_MASK = 0x3fffffffu;

struct LightBvhNode {
    PENUMBRA_LB_VEC3 boundsMin;
    float power;  // phi: summed emitted power (mean of RGB) below this node
    PENUMBRA_LB_VEC3 boundsMax;
    PENUMBRA_LB_UINT cosines;  // low 16 bits: cos theta_o, high: cos theta_e, each floor((c + 1) / 2 * 65535)
    PENUMBRA_LB_VEC3 axis;     // w: the axis of the normals' cone (unit)
    PENUMBRA_LB_UINT childOrItem;
};

// One light the tree can choose: a light (index into Light[]) or, for a mesh light, one of
// its triangles (primitive in BVH leaf order; ~0u otherwise). trail: the branch taken at
// each depth from the root, bit d = 1 for the second child (pbrt-v4's bitTrail), so that
// the probability of choosing it can be replayed exactly for MIS.
struct LightBvhItem {
    PENUMBRA_LB_UINT light;
    PENUMBRA_LB_UINT primitive;
    PENUMBRA_LB_UINT trailLow;
    PENUMBRA_LB_UINT trailHigh;
};

// What lightImportance (lights/light_importance.glsl, render/light_bvh.h) needs of a node
// besides the shading point: the light BVH derives it from a LightBvhNode at every shading
// point, the flat form of small trees (shared/light_flat.h) gets it from the host.
struct LightImportanceTerms {
    PENUMBRA_LB_VEC3 center;  // of the node's box
    float halfDiagonal2;      // the box's squared half diagonal: its bounding sphere's radius^2
    PENUMBRA_LB_VEC3 axis;    // the normals' cone (unit)
    float power;
    float cosThetaO, sinThetaO;  // the normals' cone, decoded (cosines as LightBvhNode's)
    float cosThetaE;             // how far past a normal light leaves
    PENUMBRA_LB_UINT twoSided;   // 1: emits on both sides of the cone (LIGHT_BVH_TWO_SIDED)
};

#undef PENUMBRA_LB_VEC3
#undef PENUMBRA_LB_UINT
#undef PENUMBRA_LB_CONST
#ifdef __cplusplus
}  // namespace penumbra::gpu
#endif

#endif
