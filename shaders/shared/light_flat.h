// The flat form of a small light tree (`light_selection: "bvh"` with at most
// LIGHT_FLAT_MAX_LEAVES lights, in the kernels with inline geometry; render/light_flat.h says
// when and why): each leaf of the tree, the importance terms the host derived from it, as
// specialization constants (lights/light_flat.glsl), LIGHT_FLAT_WORDS words per leaf in this
// struct's order. Shared by the C++ host and GLSL.
#ifndef PENUMBRA_SHARED_LIGHT_FLAT_H
#define PENUMBRA_SHARED_LIGHT_FLAT_H

#include "shared/light_bvh.h"
#include "shared/types.h"

#ifdef __cplusplus
namespace penumbra::gpu {
#endif

struct LightFlatLeaf {
    LightImportanceTerms terms;  // of the leaf's node, as lightBvhImportanceTerms derives them
    uint light;                  // index into Light[] (LightBvhItem.light)
    uint primitive;              // LightBvhItem.primitive: the mesh triangle chosen, else NO_HIT
    uint hitPrimitive;           // the primitive (leaf order) a BRDF-sampled ray hits it by, NO_HIT: none
};

#ifdef __cplusplus
static_assert(sizeof(LightFlatLeaf) == LIGHT_FLAT_WORDS * sizeof(uint), "LIGHT_FLAT_WORDS words per leaf");
}  // namespace penumbra::gpu
#endif

#endif
