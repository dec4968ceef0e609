// The emitter-first rule (emitter_first.h): the exactness conditions, the CPU probe of where
// BRDF-sampled rays end and what their closest hits cost, and the thresholds measured in
// docs/performance-history/round-04.md and docs/performance-history/round-05.md.
#include "render/emitter_first.h"

#include <algorithm>
#include <cmath>

#include "bvh/bvh.h"
#include "render/probe_rays.h"

namespace penumbra {

bool emitterFirstExact(const IntegratorSettings& integrator, const SceneArrays& arrays) {
    if (integrator.type != IntegratorType::Direct || integrator.strategy == Strategy::Light) return false;
    if (arrays.lights.empty() || arrays.lights.size() > kEmitterFirstMaxLights) return false;
    // The kinds allowed are listed rather than those refused: a light kind added later (one
    // that a ray can reach without hitting a sphere or quad, as an environment) keeps the
    // closest hit until it is added here.
    for (const gpu::Light& l : arrays.lights)
        if (l.type != gpu::LIGHT_SPHERE && l.type != gpu::LIGHT_QUAD && l.type != gpu::LIGHT_POINT &&
            l.type != gpu::LIGHT_SPOT && l.type != gpu::LIGHT_DIRECTIONAL)
            return false;
    return arrays.environmentLight == gpu::NO_LIGHT;
}

namespace {

constexpr int kCameraGrid = 16;  // camera rays per film axis
constexpr int kBrdfGrid = 4;     // cosine directions per axis at each camera hit

// A fixed, well-spread number in [0, 1) per (i, j): the fractional part of a 2D
// Kronecker sequence (Roberts' R2 constants), so each camera hit gets a shifted grid.
glm::vec2 shift(int i) {
    const double a = 0.7548776662466927, b = 0.5698402909980532;
    return {float(std::fmod(0.5 + a * i, 1.0)), float(std::fmod(0.5 + b * i, 1.0))};
}

}  // namespace

BrdfRayFates brdfRayFates(const Scene& scene, const SceneArrays& arrays) {
    const gpu::RenderParams p = makeRenderParams(scene, arrays);
    const Bvh& bvh = arrays.bvh;
    BrdfRayFates fates;
    int rays = 0;
    for (int py = 0; py < kCameraGrid; ++py)
        for (int px = 0; px < kCameraGrid; ++px) {
            const auto hit = probeCameraRay(bvh, p, glm::vec2((px + 0.5f) / kCameraGrid, (py + 0.5f) / kCameraGrid));
            if (!hit) continue;
            const glm::vec3 n = hit->normal;
            // Orthonormal basis around n (Duff et al. 2017, "Building an Orthonormal Basis,
            // Revisited", JCGT 6(1)).
            const float sign = std::copysign(1.0f, n.z), a = -1.0f / (sign + n.z), b = n.x * n.y * a;
            const glm::vec3 t1(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
            const glm::vec3 t2(b, sign + n.y * n.y * a, -n.y);
            const glm::vec3 origin = hit->rayOrigin;
            const glm::vec2 s = shift(py * kCameraGrid + px);
            for (int j = 0; j < kBrdfGrid; ++j)
                for (int i = 0; i < kBrdfGrid; ++i) {
                    // Cosine-weighted direction (Malley's method; PBR book 3rd ed. 13.6.3).
                    const float u1 = std::fmod((i + s.x) / kBrdfGrid, 1.0f),
                                u2 = std::fmod((j + s.y) / kBrdfGrid, 1.0f);
                    const float r = std::sqrt(u1), phi = 2.0f * float(M_PI) * u2;
                    const glm::vec3 wi = r * std::cos(phi) * t1 + r * std::sin(phi) * t2 +
                                         std::sqrt(std::max(0.0f, 1.0f - u1)) * n;
                    // Counted with node entries on the stack, as when the thresholds
                    // (emitter_first.h) were measured; child entries count a few steps fewer.
                    TraversalWork work;
                    const auto next = intersectClosest(bvh, origin, wi, 3.4e38f, &work, StackEntries::Nodes);
                    fates.closestHitWork += double(work.nodes + work.primitives);
                    if (!next) fates.escape += 1.0;
                    else if (bvh.primitives[next->primitive].light != gpu::NO_LIGHT) fates.emitter += 1.0;
                    else fates.other += 1.0;
                    ++rays;
                }
        }
    if (rays > 0) {
        fates.emitter /= rays;
        fates.other /= rays;
        fates.escape /= rays;
        fates.closestHitWork /= rays;
    }
    return fates;
}

bool emitterFirstPays(const Scene& scene, const SceneArrays& arrays) {
    if (!emitterFirstExact(scene.integrator, arrays)) return false;
    const BrdfRayFates f = brdfRayFates(scene, arrays);
    return f.closestHitWork >= kEmitterFirstMinWork && f.emitter <= kEmitterFirstMaxEmitter;
}

bool emitterFirstPaysInline(double emitter, uint32_t lights, uint32_t primitives) {
    // The share of SIMD groups in which at least one ray finds an emitter, were the rays'
    // fates independent (neighbouring pixels' rays are alike, so fewer groups do: this errs
    // toward the closest hit).
    const double groupsWithEmitter = 1.0 - std::pow(1.0 - std::clamp(emitter, 0.0, 1.0), kEmitterFirstInlineLanes);
    return double(lights) * kEmitterFirstInlineLightCost + groupsWithEmitter * double(primitives) < double(primitives);
}

bool emitterFirstPaysFor(const Scene& scene, const SceneArrays& arrays, uint32_t inlinePrimitives) {
    if (inlinePrimitives == 0) return emitterFirstPays(scene, arrays);
    if (!emitterFirstExact(scene.integrator, arrays)) return false;
    return emitterFirstPaysInline(brdfRayFates(scene, arrays).emitter, uint32_t(arrays.lights.size()),
                                  inlinePrimitives);
}

}  // namespace penumbra
