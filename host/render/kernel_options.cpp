// Integrator options and scene features -> specialization constants (see kernel_options.h).
#include "render/kernel_options.h"

#include <stdexcept>
#include <string>

namespace penumbra {

std::vector<uint32_t> KernelOptions::specialization() const {
    std::vector<uint32_t> values(SPEC_COUNT);
    values[SPEC_COUNT_RAYS] = countRays;
    values[SPEC_STRATEGY] = strategy;
    values[SPEC_HEURISTIC] = heuristic;
    values[SPEC_LIGHT_SAMPLES] = lightSamples;
    values[SPEC_BSDF_SAMPLES] = bsdfSamples;
    values[SPEC_SPHERE_SAMPLING] = sphereSampling;
    values[SPEC_AO_SAMPLING] = aoSampling;
    values[SPEC_SCENE_FEATURES] = sceneFeatures;
    values[SPEC_SAMPLER] = sampler;
    values[SPEC_QUAD_SAMPLING] = quadSampling;
    values[SPEC_TRIANGLE_SAMPLING] = triangleSampling;
    return values;
}

namespace {

// The feature bit of kind `kind` in the group starting at `first` with `count` kinds. A kind
// at or past its group's count (added to types.h without raising *_KIND_COUNT) would set a
// bit of the next group: refused here rather than compiled into the wrong kernel.
uint32_t featureBit(uint32_t first, uint32_t count, uint32_t kind) {
    if (kind >= count)
        throw std::logic_error("scene feature kind " + std::to_string(kind) + " not below its *_KIND_COUNT " +
                               std::to_string(count));
    return 1u << (first + kind);
}

}  // namespace

uint32_t sceneFeatures(const SceneArrays& arrays) {
    uint32_t bits = 0;
    for (const gpu::Primitive& p : arrays.bvh.primitives)
        bits |= featureBit(FEATURE_PRIMITIVE, PRIM_KIND_COUNT, p.typeAndNormals & gpu::PRIM_TYPE_MASK);
    for (const gpu::Light& l : arrays.lights) bits |= featureBit(FEATURE_LIGHT, LIGHT_KIND_COUNT, l.type);
    for (const gpu::Material& m : arrays.materials) bits |= featureBit(FEATURE_MATERIAL, MATERIAL_KIND_COUNT, m.type);
    return bits;
}

KernelOptions makeKernelOptions(const Scene& scene, const SceneArrays& arrays) {
    const IntegratorSettings& in = scene.integrator;
    KernelOptions o;
    if (in.type == IntegratorType::AmbientOcclusion) {
        o.aoSampling = in.aoSampling == AoSampling::Cosine ? gpu::AO_COSINE : gpu::AO_UNIFORM;
    } else {
        o.strategy = in.strategy == Strategy::Light  ? gpu::STRATEGY_LIGHT
                     : in.strategy == Strategy::Bsdf ? gpu::STRATEGY_BSDF
                     : in.strategy == Strategy::Mis  ? gpu::STRATEGY_MIS
                                                     : gpu::STRATEGY_MIXTURE;
        o.heuristic = in.heuristic == Heuristic::Power ? gpu::HEURISTIC_POWER : gpu::HEURISTIC_BALANCE;
        o.lightSamples = in.lightSamples;
        o.bsdfSamples = in.bsdfSamples;
        o.sphereSampling = in.sphereSampling == SphereSampling::Area  ? gpu::SPHERE_AREA
                           : in.sphereSampling == SphereSampling::Cap ? gpu::SPHERE_CAP
                                                                      : gpu::SPHERE_SOLID_ANGLE;
        o.quadSampling = in.quadSampling == QuadSampling::Area ? gpu::QUAD_AREA : gpu::QUAD_SOLID_ANGLE;
        o.triangleSampling = in.triangleSampling == TriangleSampling::Area ? gpu::TRIANGLE_AREA
                                                                           : gpu::TRIANGLE_SOLID_ANGLE;
    }
    o.sceneFeatures = sceneFeatures(arrays);
    o.sampler = scene.sampler.type == SamplerType::Sobol ? gpu::SAMPLER_SOBOL : gpu::SAMPLER_INDEPENDENT;
    return o;
}

}  // namespace penumbra
