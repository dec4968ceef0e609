// Camera rays traced on the CPU, as the kernels trace them, for the host's probes of a scene:
// the emitter-first rule's (render/emitter_first.cpp) and penumbra_bench --lanes'.
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "bvh/bvh.h"
#include "shared/types.h"

namespace penumbra {

// The direction of the camera ray through film point `film` ([0, 1]^2, y down): cameraRay in
// integrators/kernel_common.glsl, without its jitter.
glm::vec3 cameraRayDirection(const gpu::RenderParams& params, glm::vec2 film);

// Where a camera ray first hits: the direction it came from, the geometric normal turned
// towards it, and the origin for a secondary ray from there, lifted off the surface along
// that normal by 1e-4 (1 + |x|).
struct ProbeHit {
    glm::vec3 dir;
    glm::vec3 normal;
    glm::vec3 rayOrigin;
};

// The camera ray through `film` traced in `bvh` (its work added to `work` when given); none
// where it escapes.
std::optional<ProbeHit> probeCameraRay(const Bvh& bvh, const gpu::RenderParams& params, glm::vec2 film,
                                       TraversalWork* work = nullptr);

}  // namespace penumbra
