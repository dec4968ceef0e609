// When the direct integrator's BRDF-sampled rays test the emitters first
// (shaders/integrators/emitter_first.glsl): where that is the same estimator as the
// closest hit, and where it was measured to pay (docs/performance-history/round-04.md and
// docs/performance-history/round-05.md), judged from a few hundred CPU rays that imitate the BRDF-sampled rays of a
// render.
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

// Where rays like a render's BRDF-sampled rays end (the fractions that hit an emitter,
// hit something else, or leave the scene) and what their closest-hit traversals cost.
struct BrdfRayFates {
    double emitter = 0.0, other = 0.0, escape = 0.0;
    double closestHitWork = 0.0;  // mean wide nodes plus primitives a closest hit tests per ray
};
// Cosine-distributed rays from the first hits of a grid of camera rays, traced on the CPU
// (bvh/bvh.h) with a fixed pattern, so the answer is the same on every run.
BrdfRayFates brdfRayFates(const Scene& scene, const SceneArrays& arrays);

// emitterFirstExact, and the rule measured in docs/performance-history/round-05.md: the path
// saves the closest-hit traversal of every ray that finds no emitter, and costs an emitter
// loop for every ray and an any-hit traversal for the SIMD groups where some ray finds an
// emitter. So it pays where few rays find an emitter and the closest hit is dear: in closed
// rooms, where rays hit walls after a few steps, and on dense meshes, where even a ray that
// leaves the scene first descends through a deep tree around its origin. It loses where
// the closest hit is cheap (open scenes of a few shapes: most rays leave after a few box
// tests). With the four-wide tree the measured scenes put the break-even between 2.0 units
// of work (the MIS scene: 0.92x) and 7.0 (the glTF model: 1.22x); the threshold is where
// the straight line through those two gains crosses 1 (docs/performance-history/round-07.md).
bool emitterFirstPays(const Scene& scene, const SceneArrays& arrays);
constexpr double kEmitterFirstMinWork = 3.5;      // BrdfRayFates::closestHitWork at least
constexpr double kEmitterFirstMaxEmitter = 0.05;  // BrdfRayFates::emitter at most

// The rule for a scene whose primitives are inline (render/inline_geometry.h), where the
// closest hit is no traversal but one constant-folded test per primitive, the same for every
// ray. The path replaces those `primitives` tests with a loop over the `lights` (each read
// from memory and tested by the general intersection), and adds an occlusion test of every
// primitive for each SIMD group of kEmitterFirstInlineLanes rays in which one ray finds an
// emitter (a fraction `emitter` of the rays, BrdfRayFates::emitter). So it pays where
//   lights * kEmitterFirstInlineLightCost + (1 - (1 - emitter)^lanes) * primitives < primitives,
// costs counted in inline primitive tests. The constants were fitted to callgrind's
// instructions per sample of both paths on four inline scenes (docs/performance-history/round-29.md): a Cornell box
// with one quad light gains, a room with one sphere light gains a
// little, and rooms with three sphere lights lose 12-16%, which the BVH scenes' rule above
// (that knows no light count) took in a large room.
bool emitterFirstPaysInline(double emitter, uint32_t lights, uint32_t primitives);
constexpr double kEmitterFirstInlineLightCost = 5.0;  // inline primitive tests per light of the loop
constexpr int kEmitterFirstInlineLanes = 16;          // the SIMD width lavapipe uses on Mesa 25 with AVX-512

// emitterFirstExact, and the rule for the kernel the scene gets: emitterFirstPaysInline
// where its `inlinePrimitives` (> 0) are inline, emitterFirstPays otherwise.
bool emitterFirstPaysFor(const Scene& scene, const SceneArrays& arrays, uint32_t inlinePrimitives);

}  // namespace penumbra
