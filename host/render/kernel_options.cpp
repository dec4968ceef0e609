// Integrator options and scene features -> specialization constants (see kernel_options.h).
#include "render/kernel_options.h"

#include "render/aov_layers.h"
#include "render/light_bvh_arrays.h"
#include "render/light_flat.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace penumbra {

// The scene enums number their values as the shaders' constants do, so an option is passed
// as its enum value.
static_assert(uint32_t(AoSampling::Uniform) == gpu::AO_UNIFORM && uint32_t(AoSampling::Cosine) == gpu::AO_COSINE);
static_assert(uint32_t(Strategy::Light) == gpu::STRATEGY_LIGHT && uint32_t(Strategy::Bsdf) == gpu::STRATEGY_BSDF &&
              uint32_t(Strategy::Mis) == gpu::STRATEGY_MIS && uint32_t(Strategy::Mixture) == gpu::STRATEGY_MIXTURE &&
              uint32_t(Strategy::Ris) == gpu::STRATEGY_RIS);
static_assert(uint32_t(Heuristic::Balance) == gpu::HEURISTIC_BALANCE &&
              uint32_t(Heuristic::Power) == gpu::HEURISTIC_POWER);
static_assert(uint32_t(SphereSampling::Area) == gpu::SPHERE_AREA && uint32_t(SphereSampling::Cap) == gpu::SPHERE_CAP &&
              uint32_t(SphereSampling::SolidAngle) == gpu::SPHERE_SOLID_ANGLE);
static_assert(uint32_t(QuadSampling::Area) == gpu::QUAD_AREA &&
              uint32_t(QuadSampling::SolidAngle) == gpu::QUAD_SOLID_ANGLE);
static_assert(uint32_t(TriangleSampling::Area) == gpu::TRIANGLE_AREA &&
              uint32_t(TriangleSampling::SolidAngle) == gpu::TRIANGLE_SOLID_ANGLE);
static_assert(uint32_t(SamplerType::Independent) == gpu::SAMPLER_INDEPENDENT &&
              uint32_t(SamplerType::Sobol) == gpu::SAMPLER_SOBOL);

std::vector<uint32_t> KernelOptions::specialization() const {
    // The options of the other integrator type stay at their defaults, so that they do not
    // split the pipeline cache.
    const IntegratorSettings defaults;
    const bool ao = integrator.type == IntegratorType::AmbientOcclusion;
    const IntegratorSettings& direct = ao ? defaults : integrator;
    const AoSampling aoSampling = ao ? integrator.aoSampling : defaults.aoSampling;
    std::vector<uint32_t> values(SPEC_COUNT);
    values[SPEC_COUNT_RAYS] = countRays;
    values[SPEC_STRATEGY] = uint32_t(direct.strategy);
    values[SPEC_HEURISTIC] = uint32_t(direct.heuristic);
    values[SPEC_LIGHT_SAMPLES] = direct.lightSamples;
    values[SPEC_BSDF_SAMPLES] = direct.bsdfSamples;
    values[SPEC_SPHERE_SAMPLING] = uint32_t(direct.sphereSampling);
    values[SPEC_AO_SAMPLING] = uint32_t(aoSampling);
    values[SPEC_SCENE_FEATURES] = sceneFeatures;
    values[SPEC_SAMPLER] = uint32_t(sampler);
    values[SPEC_QUAD_SAMPLING] = uint32_t(direct.quadSampling);
    values[SPEC_TRIANGLE_SAMPLING] = uint32_t(direct.triangleSampling);
    values[SPEC_TEXTURES] = textures;
    values[SPEC_EMITTER_FIRST] = ao ? 0u : emitterFirstLights;
    values[SPEC_INLINE_COUNT] = inlineGeometry.slotCount();
    std::copy(inlineGeometry.slots.begin(), inlineGeometry.slots.end(), values.begin() + SPEC_INLINE_FIRST);
    std::copy(inlineGeometry.groups.begin(), inlineGeometry.groups.end(), values.begin() + SPEC_INLINE_GROUP_FIRST);
    values[SPEC_NODE_READS] = nodeReads;
    values[SPEC_LOOPS_MAY_BE_CUT] = loopsMayBeCut;
    values[SPEC_AOVS] = aovs;
    values[SPEC_LIGHT_BVH] = ao ? 0u : lightBvh;
    // Only "ris" reads it: other strategies keep the default, so it does not split their cache.
    values[SPEC_RIS_CANDIDATES] = direct.strategy == Strategy::Ris ? direct.risCandidates : defaults.risCandidates;
    const std::vector<uint32_t>& flat = ao ? std::vector<uint32_t>{} : lightFlat;
    values[SPEC_LIGHT_FLAT_COUNT] = uint32_t(flat.size() / LIGHT_FLAT_WORDS);
    values[SPEC_LIGHT_FLAT_ALONE] = flat.empty() ? 0u : lightFlatAlone;
    std::copy(flat.begin(), flat.end(), values.begin() + SPEC_LIGHT_FLAT_FIRST);
    return values;
}

uint32_t KernelOptions::lightAndBsdfSamples() const {
    const std::vector<uint32_t> values = specialization();
    if (values[SPEC_STRATEGY] == gpu::STRATEGY_RIS) return values[SPEC_LIGHT_SAMPLES] * (values[SPEC_BSDF_SAMPLES] + 1);
    return values[SPEC_LIGHT_SAMPLES] + values[SPEC_BSDF_SAMPLES];
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
    for (const gpu::Light& l : arrays.lights) {
        bits |= featureBit(FEATURE_LIGHT, LIGHT_KIND_COUNT, l.type);
        if (l.type == gpu::LIGHT_ENVIRONMENT && (l.flags & gpu::LIGHT_ENVIRONMENT_MAP))
            bits |= 1u << FEATURE_ENVIRONMENT_MAP;
        if (l.type == gpu::LIGHT_QUAD && !(l.flags & gpu::LIGHT_RECTANGLE)) bits |= 1u << FEATURE_PARALLELOGRAM_LIGHT;
    }
    if (arrays.lights.size() == 1) bits |= 1u << FEATURE_SINGLE_LIGHT;
    for (const gpu::Material& m : arrays.materials) bits |= featureBit(FEATURE_MATERIAL, MATERIAL_KIND_COUNT, m.type);
    return bits;
}

// SPEC_EMITTER_FIRST holds the light count, which the kernel loops over: every light, at
// most kEmitterFirstMaxLights of them.
static_assert(kEmitterFirstMaxLights > 0 && SPEC_EMITTER_FIRST < SPEC_COUNT);

KernelOptions makeKernelOptions(const Scene& scene, const SceneArrays& arrays, EmitterFirst emitterFirst,
                                InlineGeometry inlineGeometry) {
    KernelOptions o;
    o.integrator = scene.integrator;
    o.sampler = scene.sampler.type;
    o.sceneFeatures = sceneFeatures(arrays);
    o.textures = (arrays.textures.textured ? TEXTURES_ON : 0u) |
                 (arrays.textures.transformed ? TEXTURES_TRANSFORMED : 0u) |
                 (arrays.textures.emission ? TEXTURES_EMISSION : 0u) |
                 (arrays.textures.alphaMask ? TEXTURES_ALPHA_MASK : 0u) |
                 (arrays.textures.normalMap ? TEXTURES_NORMAL_MAP : 0u);
    // The alpha test sits in the BVH traversal's triangle hits (textures/alpha_mask.glsl):
    // scenes with one trace through the BVH, neither inline nor emitter first.
    const bool masked = arrays.textures.alphaMask;
    const bool inlined = !masked && inlineGeometry == InlineGeometry::Rule && inlineGeometryPays(arrays);
    if (inlined) o.inlineGeometry = inlineGeometryWords(arrays.bvh);
    // Inline scenes have a rule of their own (emitter_first.h): on Mesa 25, which skips the
    // branches no SIMD lane takes, a BRDF-sampled ray that misses every emitter skips the
    // occlusion test and the emitter's surface point, as through the BVH, but the closest
    // hit it saves is cheap (docs/performance-history/round-09.md and docs/performance-history/round-29.md).
    const uint32_t inlinePrimitives = inlined ? uint32_t(arrays.bvh.primitives.size()) : 0u;
    const bool on = masked                                ? false
                    : emitterFirst == EmitterFirst::Exact ? emitterFirstExact(scene.integrator, arrays)
                    : emitterFirst == EmitterFirst::Rule  ? emitterFirstPaysFor(scene, arrays, inlinePrimitives)
                                                          : false;
    o.emitterFirstLights = on ? uint32_t(arrays.lights.size()) : 0u;
    o.aovs = aovBits(scene.film.aovs);
    o.lightBvh = scene.integrator.lightSelection == LightSelection::Bvh ? 1u : 0u;
    if (o.lightBvh && lightFlatPays(arrays.lightBvh.tree.items.size(), inlined)) {
        o.lightFlat = lightFlatWords(lightFlatLeaves(arrays.lightBvh.tree, lightBvhHitPrimitives(arrays)));
        o.lightFlatAlone = arrays.lightBvh.tableCount == 1 ? 1u : 0u;  // the tree's own entry alone
    }
    return o;
}

}  // namespace penumbra
