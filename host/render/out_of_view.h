// Which primitive beside the tree no camera ray can hit, so that the kernels leave its test
// out of camera rays (shaders/geometry/bvh.glsl, `ignore`): a light above the view, say,
// which every camera ray would otherwise test before the tree.
#pragma once

#include <cstdint>

#include "bvh/bvh.h"
#include "shared/types.h"

namespace penumbra {

// The first primitive beside the tree of `bvh` whose bounding box lies wholly outside the
// camera's view (params: eye, basis, field of view and aspect, as cameraRay in
// integrators/kernel_common.glsl spans it), or NO_HIT. Conservative: a box counts as outside
// only where every corner is beyond the same side of the view pyramid by a relative margin
// far above float rounding, so a ray that could meet the primitive is never denied it.
uint32_t besideOutOfView(const gpu::RenderParams& params, const Bvh& bvh);

}  // namespace penumbra
