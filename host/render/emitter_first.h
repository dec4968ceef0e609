// When the direct integrator's BRDF-sampled rays test the emitters first
// (shaders/integrators/emitter_first.glsl): where that is the same estimator as the
// closest hit, and where it was measured to pay (docs/PERFORMANCE.md, "Round 4"), judged
// from a few hundred CPU rays that imitate the BRDF-sampled rays of a render.
#pragma once

#include <cstdint>

#include "render/scene_arrays.h"
#include "scene/scene.h"

namespace penumbra {

// Which way BRDF-sampled rays find the emitter they hit.
enum class EmitterFirst {
    Rule,   // emitter first where emitterFirstPays says so (every render)
    Off,    // always the closest hit
    Exact,  // emitter first wherever emitterFirstExact holds (tests and benchmarks compare)
};

// The kernel tests the first kEmitterFirstMaxLights lights at most, one by one.
constexpr uint32_t kEmitterFirstMaxLights = 8;

// Whether the emitter-first path is the same estimator as the closest hit: `integrator`
// traces BRDF-sampled rays (direct, strategy bsdf, mis or mixture) and the scene has 1 to
// kEmitterFirstMaxLights lights, each a sphere, a quad or a delta light (no mesh emitter, no
// environment: a ray that hits no sphere or quad emitter gathers nothing).
bool emitterFirstExact(const IntegratorSettings& integrator, const SceneArrays& arrays);

// Where rays like a render's BRDF-sampled rays end: the fractions that hit an emitter,
// hit something else, or leave the scene.
struct BrdfRayFates {
    double emitter = 0.0, other = 0.0, escape = 0.0;
};
// Cosine-distributed rays from the first hits of a grid of camera rays, traced on the CPU
// (bvh/bvh.h) with a fixed pattern, so the answer is the same on every run.
BrdfRayFates brdfRayFates(const Scene& scene, const SceneArrays& arrays);

// emitterFirstExact, and the rule measured in docs/PERFORMANCE.md ("Round 4"): the path
// saves the closest-hit traversal of rays that would hit something other than an emitter
// and costs an emitter loop for every ray and an any-hit traversal for SIMD groups where
// some ray finds an emitter; so it pays where most rays hit other surfaces (closed rooms)
// and few find an emitter.
bool emitterFirstPays(const Scene& scene, const SceneArrays& arrays);
constexpr double kEmitterFirstMinOther = 0.5;     // BrdfRayFates::other at least
constexpr double kEmitterFirstMaxEmitter = 0.05;  // BrdfRayFates::emitter at most

}  // namespace penumbra
