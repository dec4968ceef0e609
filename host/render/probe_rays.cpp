// Camera rays traced on the CPU (see probe_rays.h).
#include "render/probe_rays.h"

#include "bvh/intersect.h"

namespace penumbra {

glm::vec3 cameraRayDirection(const gpu::RenderParams& p, glm::vec2 film) {
    const float x = (2.0f * film.x - 1.0f) * p.aspect * p.tanHalfFovY;
    const float y = (1.0f - 2.0f * film.y) * p.tanHalfFovY;
    return glm::normalize(p.forward + x * p.right + y * p.up);
}

std::optional<ProbeHit> probeCameraRay(const Bvh& bvh, const gpu::RenderParams& p, glm::vec2 film,
                                       TraversalWork* work) {
    const glm::vec3 dir = cameraRayDirection(p, film);
    const auto hit = intersectClosest(bvh, p.eye, dir, 3.4e38f, work);
    if (!hit) return std::nullopt;
    const glm::vec3 x = p.eye + hit->t * dir;
    glm::vec3 n = glm::normalize(primitiveNormal(bvh.primitives[hit->primitive], x));
    if (glm::dot(n, dir) > 0.0f) n = -n;
    return ProbeHit{dir, n, x + n * (1e-4f * (1.0f + glm::length(x)))};
}

}  // namespace penumbra
