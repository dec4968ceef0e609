// The AOV layers (SCENE_FORMAT.md "AOVs (v3)") as the render kernels accumulate them:
// which layers a kernel computes (SPEC_AOVS, a bit each) and the per-pixel sums in the AOV
// buffer (BINDING_AOV), shared by the GLSL (integrators/aov.glsl) and the host
// (render/aov_layers.cpp), which turns the sums into the EXR's layers.
#ifndef PENUMBRA_SHARED_AOV_H
#define PENUMBRA_SHARED_AOV_H

#include "shared/types.h"

#ifdef __cplusplus
namespace penumbra::gpu {
#endif

// SPEC_AOVS bits. 0 compiles every AOV line out of the kernel: scenes without AOVs get the
// same code, and the same image bit for bit, as before AOVs existed.
PENUMBRA_CONST uint AOV_ALBEDO = 1u;
PENUMBRA_CONST uint AOV_NORMAL = 2u;
PENUMBRA_CONST uint AOV_POSITION = 4u;
PENUMBRA_CONST uint AOV_DEPTH = 8u;
// The three ids need only the primitive that the pixel centre's ray hits: the host maps it to
// shape, triangle and material (render/aov_layers.cpp).
PENUMBRA_CONST uint AOV_SHAPE_ID = 16u;
PENUMBRA_CONST uint AOV_PRIMITIVE_ID = 32u;
PENUMBRA_CONST uint AOV_MATERIAL_ID = 64u;
PENUMBRA_CONST uint AOV_VARIANCE = 128u;
PENUMBRA_CONST uint AOV_IDS = AOV_SHAPE_ID | AOV_PRIMITIVE_ID | AOV_MATERIAL_ID;

// A pixel's AOV sums, AOV_VEC4S vec4s from pixel * AOV_VEC4S, over the same samples as the
// image (every sample the pixel's radiance sum counts, counted again in `count`):
//   [0] albedo sum (rgb), count (w)
//   [1] normal sum (xyz), depth sum over the samples that hit (w)
//   [2] position sum (xyz), samples that hit (w)
//   [3] sum of squared radiance (rgb, for the variance), centre ray's primitive (w, uint
//       bits, leaf order; NO_HIT on a miss)
PENUMBRA_CONST uint AOV_VEC4S = 4u;

#ifdef __cplusplus
}  // namespace penumbra::gpu
#endif
#endif
