// Integrator options and scene features -> specialization constants (see kernel_options.h).
#include "render/kernel_options.h"

#include "render/aov_layers.h"
#include "render/light_bvh_arrays.h"
#include "render/light_flat.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace penumbra {

std::vector<uint32_t> KernelOptions::specialization() const {
    // An option not in effect (another integrator type's, ris_candidates under another
    // strategy) gets its default, so that it does not split the pipeline cache.
    const IntegratorSettings defaults;
    const bool ao = integrator.type == IntegratorType::AmbientOcclusion;
    std::vector<uint32_t> values(SPEC_COUNT);
    for (const IntegratorOption& option : integratorOptions())
        if (option.specId != kNoSpecialization)
            values[size_t(option.specId)] =
                kernelValue(option, optionInEffect(option, integrator) ? integrator : defaults);
    values[SPEC_COUNT_RAYS] = countRays;
    values[SPEC_SCENE_FEATURES] = sceneFeatures;
    values[SPEC_SAMPLER] = kernelConstant(sampler);
    values[SPEC_TEXTURES] = textures;
    values[SPEC_EMITTER_FIRST] = ao ? 0u : emitterFirstLights;
    values[SPEC_INLINE_COUNT] = inlineGeometry.slotCount();
    std::copy(inlineGeometry.slots.begin(), inlineGeometry.slots.end(), values.begin() + SPEC_INLINE_FIRST);
    std::copy(inlineGeometry.groups.begin(), inlineGeometry.groups.end(), values.begin() + SPEC_INLINE_GROUP_FIRST);
    values[SPEC_NODE_READS] = nodeReads;
    values[SPEC_LOOPS_MAY_BE_CUT] = loopsMayBeCut;
    values[SPEC_AOVS] = aovs;
    values[SPEC_LIGHT_BVH] = ao ? 0u : lightBvh;
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
    for (const std::vector<gpu::Primitive>* prims : {&arrays.bvh.primitives, &arrays.instanced.primitives})
        for (const gpu::Primitive& p : *prims)
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
    // So does a scene with instances (geometry/instances.glsl: render/instance_arrays.h).
    const bool bvhOnly = masked || !arrays.instanced.instances.empty();
    const bool inlined = !bvhOnly && inlineGeometry == InlineGeometry::Rule && inlineGeometryPays(arrays);
    if (inlined) o.inlineGeometry = inlineGeometryWords(arrays.bvh);
    // Inline scenes have a rule of their own (emitter_first.h): on Mesa 25, which skips the
    // branches no SIMD lane takes, a BRDF-sampled ray that misses every emitter skips the
    // occlusion test and the emitter's surface point, as through the BVH, but the closest
    // hit it saves is cheap (docs/performance-history/round-09.md and docs/performance-history/round-29.md).
    const uint32_t inlinePrimitives = inlined ? uint32_t(arrays.bvh.primitives.size()) : 0u;
    const bool on = bvhOnly                               ? false
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
