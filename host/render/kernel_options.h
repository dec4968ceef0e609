// The specialization constants of a render kernel (SPEC_* in shaders/shared/types.h):
// integrator options and the kinds of primitives, lights and materials a scene contains.
// Each distinct set is its own pipeline, compiled by the driver on first use.
#pragma once

#include <cstdint>
#include <vector>

#include "render/scene_arrays.h"
#include "scene/scene.h"

namespace penumbra {

struct KernelOptions {
    uint32_t countRays = 0;
    uint32_t strategy = gpu::STRATEGY_MIS;
    uint32_t heuristic = gpu::HEURISTIC_POWER;
    uint32_t lightSamples = 1;
    uint32_t bsdfSamples = 1;
    uint32_t sphereSampling = gpu::SPHERE_SOLID_ANGLE;
    uint32_t aoSampling = gpu::AO_COSINE;
    uint32_t sceneFeatures = gpu::FEATURES_ALL;
    uint32_t sampler = gpu::SAMPLER_SOBOL;
    uint32_t quadSampling = gpu::QUAD_SOLID_ANGLE;
    uint32_t triangleSampling = gpu::TRIANGLE_AREA;
    uint32_t textures = 0;  // 1: some material is textured

    // Values in constant_id order, for gpu::Pipeline.
    std::vector<uint32_t> specialization() const;
    bool operator==(const KernelOptions&) const = default;
};

// The options of `scene`'s integrator (those of the other integrator type stay at their
// defaults, so that they do not split the pipeline cache) and sampler, and the features of
// `arrays`.
KernelOptions makeKernelOptions(const Scene& scene, const SceneArrays& arrays);

// FEATURE_* bits of what `arrays` contains.
uint32_t sceneFeatures(const SceneArrays& arrays);

}  // namespace penumbra
