// Integrator options and scene features -> specialization constants (see kernel_options.h).
#include "render/kernel_options.h"

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
    values[SPEC_TEXTURES] = textures;
    return values;
}

uint32_t sceneFeatures(const SceneArrays& arrays) {
    uint32_t bits = 0;
    for (const gpu::Primitive& p : arrays.bvh.primitives) bits |= 1u << (FEATURE_PRIMITIVE + (p.typeAndNormals & gpu::PRIM_TYPE_MASK));
    for (const gpu::Light& l : arrays.lights) bits |= 1u << (FEATURE_LIGHT + l.type);
    for (const gpu::Material& m : arrays.materials) bits |= 1u << (FEATURE_MATERIAL + m.type);
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
    o.textures = arrays.textures.textured ? 1u : 0u;
    o.sampler = scene.sampler.type == SamplerType::Sobol ? gpu::SAMPLER_SOBOL : gpu::SAMPLER_INDEPENDENT;
    return o;
}

}  // namespace penumbra
