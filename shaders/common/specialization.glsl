// The render kernels' specialization constants (ids and meaning in shared/types.h, values
// from host/render/kernel_options.cpp). Declared in one place so every file tests the same
// constant; the defaults keep every code path, for kernels that never set them (the
// shader tests).
#ifndef PENUMBRA_SPECIALIZATION_GLSL
#define PENUMBRA_SPECIALIZATION_GLSL

#include "shared/types.h"

layout(constant_id = SPEC_COUNT_RAYS) const uint kCountRays = 0u;
layout(constant_id = SPEC_STRATEGY) const uint kStrategy = STRATEGY_MIS;
layout(constant_id = SPEC_HEURISTIC) const uint kHeuristic = HEURISTIC_POWER;
layout(constant_id = SPEC_LIGHT_SAMPLES) const uint kLightSamples = 1u;
layout(constant_id = SPEC_BSDF_SAMPLES) const uint kBsdfSamples = 1u;
layout(constant_id = SPEC_SPHERE_SAMPLING) const uint kSphereSampling = SPHERE_SOLID_ANGLE;
layout(constant_id = SPEC_AO_SAMPLING) const uint kAoSampling = AO_COSINE;
layout(constant_id = SPEC_SCENE_FEATURES) const uint kSceneFeatures = FEATURES_ALL;
layout(constant_id = SPEC_SAMPLER) const uint kSampler = SAMPLER_SOBOL;
layout(constant_id = SPEC_QUAD_SAMPLING) const uint kQuadSampling = QUAD_SOLID_ANGLE;
layout(constant_id = SPEC_TRIANGLE_SAMPLING) const uint kTriangleSampling = TRIANGLE_AREA;
// Off unless set: kernels without the texture bindings (the shader tests) never read them.
layout(constant_id = SPEC_TEXTURES) const uint kTextures = 0u;
// Off unless set: the emitter-first path is exact only for scenes the host's rule checked.
layout(constant_id = SPEC_EMITTER_FIRST) const uint kEmitterFirstLights = 0u;

// Texel fetches unless set: the shader tests run both (tests/test_bvh.cpp).
layout(constant_id = SPEC_NODE_READS) const uint kNodeReads = NODE_READS_TEXELS;

// Off unless set: on for drivers that may end a shader's loops early (render/loop_budget.h).
layout(constant_id = SPEC_LOOPS_MAY_BE_CUT) const uint kLoopsMayBeCut = 0u;

// Off unless set: the AOV_* layers to accumulate (integrators/aov.glsl); 0 compiles them out.
layout(constant_id = SPEC_AOVS) const uint kAovs = 0u;

// Off unless set: light_selection "bvh" (integrators/light_selection_bvh.glsl); 0 compiles it out.
layout(constant_id = SPEC_LIGHT_BVH) const uint kLightBvh = 0u;

// Strategy "ris" alone reads it (integrators/ris.glsl): ris_candidates, M.
layout(constant_id = SPEC_RIS_CANDIDATES) const uint kRisCandidates = 8u;

// Whether the scene has a primitive / light / material of this type; false compiles the
// code that handles it out of the kernel.
bool hasPrimitive(uint type) { return (kSceneFeatures & (1u << (FEATURE_PRIMITIVE + type))) != 0u; }
bool hasLight(uint type) { return (kSceneFeatures & (1u << (FEATURE_LIGHT + type))) != 0u; }
bool hasMaterial(uint type) { return (kSceneFeatures & (1u << (FEATURE_MATERIAL + type))) != 0u; }
// Whether the scene's environment has a map; false compiles the map's lookup and sampling out.
bool hasEnvironmentMap() { return (kSceneFeatures & (1u << FEATURE_ENVIRONMENT_MAP)) != 0u; }
// Whether some quad light is no rectangle; false compiles its two-triangle sampling out.
bool hasParallelogramLights() { return (kSceneFeatures & (1u << FEATURE_PARALLELOGRAM_LIGHT)) != 0u; }
// Whether the scene has exactly one light (light 0).
bool hasSingleLight() { return (kSceneFeatures & (1u << FEATURE_SINGLE_LIGHT)) != 0u; }
// Whether any material is textured; false compiles texture coordinates and lookups out.
bool hasTextures() { return kTextures != 0u; }
// Whether some texture reference has a uv transform (glTF KHR_texture_transform); false
// compiles the transform out and keeps the references TEXTURE_REF_TEXELS apart.
bool hasTextureTransforms() { return (kTextures & TEXTURES_TRANSFORMED) != 0u; }
// Whether some emitter's material has an emission texture (glTF emissiveTexture); false
// compiles its lookups out of emission and light sampling.
bool hasEmissionTextures() { return (kTextures & TEXTURES_EMISSION) != 0u; }
// Whether some material has an alpha test (glTF alphaMode MASK); false compiles it out of
// every ray's triangle hits.
bool hasAlphaMask() { return (kTextures & TEXTURES_ALPHA_MASK) != 0u; }
// Whether some material has a normal map (glTF normalTexture); false compiles the tangents
// and the lookup out (textures/normal_map.glsl).
bool hasNormalMaps() { return (kTextures & TEXTURES_NORMAL_MAP) != 0u; }

// Type tests that are false at compile time for kinds the scene lacks.
bool lightIs(Light light, uint type) { return hasLight(type) && light.type == type; }
bool materialIs(Material m, uint type) { return hasMaterial(type) && m.type == type; }

#endif
