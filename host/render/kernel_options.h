// The specialization constants of a render kernel (SPEC_* in shaders/shared/types.h):
// integrator options and the kinds of primitives, lights and materials a scene contains.
// Each distinct set is its own pipeline, compiled by the driver on first use.
#pragma once

#include <cstdint>
#include <vector>

#include "render/emitter_first.h"
#include "render/inline_geometry.h"
#include "render/scene_arrays.h"
#include "scene/scene.h"

namespace penumbra {

struct KernelOptions {
    IntegratorSettings integrator;  // only the options of integrator.type reach the kernel
    SamplerType sampler = SamplerType::Sobol;
    uint32_t sceneFeatures = gpu::FEATURES_ALL;
    uint32_t countRays = 0;
    uint32_t textures = 0;                   // TEXTURES_* bits (shared/types.h)
    uint32_t emitterFirstLights = 0;         // 0, or the light count: emitter-first BRDF rays
    InlineGeometryWords inlineGeometry;      // no slots, or the primitives inline (render/inline_geometry.h)
    uint32_t nodeReads = NODE_READS_TEXELS;  // NODE_READS_*: set per device (render/node_reads.h)
    uint32_t loopsMayBeCut = 0;              // 1: set per device (render/loop_budget.h)
    uint32_t aovs = 0;                       // AOV_* bits of film.aovs (shared/aov.h); 0: none compiled
    uint32_t lightBvh = 0;                   // 1: light_selection "bvh" (lights/light_bvh.glsl)
    std::vector<uint32_t> lightFlat;         // empty, or a small tree's leaves as constants (render/light_flat.h)
    uint32_t lightFlatAlone = 0;             // 1: with lightFlat, no lights at infinity beside the tree

    // Values in constant_id order, for gpu::Pipeline.
    std::vector<uint32_t> specialization() const;
    // N1 + N2 as the kernel takes them (their defaults in an ao kernel): the samples that
    // may each trace a ray and a shadow ray. Under "ris", each of the N1 draws traces N2 BRDF
    // candidates' rays and one shadow ray: N1 (N2 + 1).
    uint32_t lightAndBsdfSamples() const;
    // Equal when they make the same pipeline.
    bool operator==(const KernelOptions& other) const { return specialization() == other.specialization(); }
};

// The integrator and sampler settings of `scene`, the features of `arrays`, and whether
// BRDF-sampled rays go emitter first (render/emitter_first.h).
KernelOptions makeKernelOptions(const Scene& scene, const SceneArrays& arrays,
                                EmitterFirst emitterFirst = EmitterFirst::Rule,
                                InlineGeometry inlineGeometry = InlineGeometry::Rule);

// FEATURE_* bits of what `arrays` contains.
uint32_t sceneFeatures(const SceneArrays& arrays);

}  // namespace penumbra
