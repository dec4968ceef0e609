// The flat form of a small light tree (render/light_flat.h: `light_selection: "bvh"` with at
// most LIGHT_FLAT_MAX_LEAVES lights, in the kernels with inline geometry): instead of the
// descent of lights/light_bvh.glsl, every leaf's importance at the shading point is computed
// and one leaf is taken from the CDF over them; the same importances give the probability
// that MIS replays for a BRDF-sampled ray that hits a leaf's emitter. The leaves' importance
// terms (shared/light_flat.h) are specialization constants that the host derived from the
// tree's leaves, so that the selection reads no memory and computes per leaf only what
// depends on the point (docs/performance-history/many-lights.md, "Four lights").
//
// The distribution differs from the descent's (a leaf's weight is its own importance, not a
// product of its ancestors' ratios) and is as exact: what is sampled and what is replayed are
// the same expressions of the same constants at the same point. As the descent does where
// both children's bounds are zero, the leaves are weighted by their powers where every
// importance is zero, so that every light keeps a probability and the pmf sums to 1.
// Mirrors host/render/light_flat.cpp operation for operation (tests/test_light_flat.cpp).
#ifndef PENUMBRA_LIGHT_FLAT_GLSL
#define PENUMBRA_LIGHT_FLAT_GLSL

#include "shared/types.h"
#include "shared/light_flat.h"
#include "lights/light_importance.glsl"

// How many leaves are in use (0: none, the kernel descends the tree in its texels).
layout(constant_id = SPEC_LIGHT_FLAT_COUNT) const uint kLightFlatCount = 0u;
// 1: no light is at infinity, so the tree is chosen with probability 1 (shared/types.h).
layout(constant_id = SPEC_LIGHT_FLAT_ALONE) const uint kLightFlatAlone = 0u;

// Leaf k's words, in shared/light_flat.h's LightFlatLeaf order: the terms (center, squared
// half diagonal, axis, power, cos and sin theta_o, cos theta_e, two-sided), the light, the
// item's primitive and the primitive a BRDF-sampled ray hits it by.
#define LIGHT_FLAT_ID(k, w) (SPEC_LIGHT_FLAT_FIRST + LIGHT_FLAT_WORDS * (k) + (w))
#define LIGHT_FLAT_FLOAT(k, w) layout(constant_id = LIGHT_FLAT_ID(k, w)) const float kLightFlat##k##_##w = 0.0;
#define LIGHT_FLAT_UINT(k, w) layout(constant_id = LIGHT_FLAT_ID(k, w)) const uint kLightFlat##k##_##w = 0u;
#define LIGHT_FLAT_LEAF(k)                                                                              \
    LIGHT_FLAT_FLOAT(k, 0) LIGHT_FLAT_FLOAT(k, 1) LIGHT_FLAT_FLOAT(k, 2) LIGHT_FLAT_FLOAT(k, 3)         \
    LIGHT_FLAT_FLOAT(k, 4) LIGHT_FLAT_FLOAT(k, 5) LIGHT_FLAT_FLOAT(k, 6) LIGHT_FLAT_FLOAT(k, 7)         \
    LIGHT_FLAT_FLOAT(k, 8) LIGHT_FLAT_FLOAT(k, 9) LIGHT_FLAT_FLOAT(k, 10) LIGHT_FLAT_UINT(k, 11)        \
    LIGHT_FLAT_UINT(k, 12) LIGHT_FLAT_UINT(k, 13) LIGHT_FLAT_UINT(k, 14)
LIGHT_FLAT_LEAF(0) LIGHT_FLAT_LEAF(1) LIGHT_FLAT_LEAF(2) LIGHT_FLAT_LEAF(3)
LIGHT_FLAT_LEAF(4) LIGHT_FLAT_LEAF(5) LIGHT_FLAT_LEAF(6) LIGHT_FLAT_LEAF(7)
#if LIGHT_FLAT_MAX_LEAVES != 8 || LIGHT_FLAT_WORDS != 15
#error "light_flat.glsl declares eight leaves of fifteen words"
#endif

#define LIGHT_FLAT_TERMS(k)                                                                             \
    LightImportanceTerms(vec3(kLightFlat##k##_0, kLightFlat##k##_1, kLightFlat##k##_2), kLightFlat##k##_3, \
                         vec3(kLightFlat##k##_4, kLightFlat##k##_5, kLightFlat##k##_6), kLightFlat##k##_7, \
                         kLightFlat##k##_8, kLightFlat##k##_9, kLightFlat##k##_10, kLightFlat##k##_11)
#define LIGHT_FLAT_EACH(F) F(0) F(1) F(2) F(3) F(4) F(5) F(6) F(7)

bool lightFlatSelection() { return kLightFlatCount != 0u; }
bool lightFlatAlone() { return kLightFlatCount != 0u && kLightFlatAlone != 0u; }

// Every leaf's weight at (p, n) and their sum: the importances, or the powers where all are 0.
// Leaves past kLightFlatCount are compiled out (constant conditions) and weigh 0.
void lightFlatWeights(vec3 p, vec3 n, out float w[LIGHT_FLAT_MAX_LEAVES], out float total) {
#define LIGHT_FLAT_IMPORTANCE(k) w[k] = uint(k) < kLightFlatCount ? lightImportance(LIGHT_FLAT_TERMS(k), p, n) : 0.0;
    LIGHT_FLAT_EACH(LIGHT_FLAT_IMPORTANCE)
#undef LIGHT_FLAT_IMPORTANCE
    total = 0.0;
    for (uint k = 0u; k < kLightFlatCount; ++k) total += w[k];
    if (!(total > 0.0)) {
// (An if, not ?:, which would make a spec-constant Select of floats that spirv-opt's folding
// leaves for the driver: gpu/spirv_specialization.cpp freezes every constant itself.)
#define LIGHT_FLAT_POWER(k) w[k] = 0.0; if (uint(k) < kLightFlatCount) w[k] = kLightFlat##k##_7;
        LIGHT_FLAT_EACH(LIGHT_FLAT_POWER)
#undef LIGHT_FLAT_POWER
        total = 0.0;
        for (uint k = 0u; k < kLightFlatCount; ++k) total += w[k];
    }
}

// A leaf chosen at (p, n) with one uniform number u in [0, 1): the first leaf of positive
// weight whose running sum exceeds u times the total (the last such leaf where rounding
// leaves u times the total at the total), and its probability `pmf`, weight over total.
uint sampleLightFlat(vec3 p, vec3 n, float u, out float pmf) {
    float w[LIGHT_FLAT_MAX_LEAVES];
    float total;
    lightFlatWeights(p, n, w, total);
    float target = u * total, below = 0.0, chosen = 0.0;
    uint leaf = 0u;
    bool found = false;
    for (uint k = 0u; k < kLightFlatCount; ++k) {
        below += w[k];
        if (!found && w[k] > 0.0) {
            leaf = k;
            chosen = w[k];
            found = target < below;
        }
    }
    pmf = chosen / total;
    return leaf;
}

// The probability that sampleLightFlat at (p, n) chooses `leaf` (beyond the leaves: 0).
float lightFlatPmf(vec3 p, vec3 n, uint leaf) {
    float w[LIGHT_FLAT_MAX_LEAVES];
    float total;
    lightFlatWeights(p, n, w, total);
    float chosen = 0.0;
    for (uint k = 0u; k < kLightFlatCount; ++k) chosen = k == leaf ? w[k] : chosen;
    return chosen / total;
}

// Leaf `leaf`'s light, its item's primitive (a mesh light's triangle, else NO_HIT), the
// primitive a BRDF-sampled ray hits it by (NO_HIT: none), and the leaf a BRDF-sampled ray
// reaches by hitting `primitive` (LIGHT_FLAT_MAX_LEAVES: none).
// (word 12, 13 or 14 of the leaf's LIGHT_FLAT_WORDS; `word` is a constant at every call, so
// the selection folds away.)
uint lightFlatWord(uint leaf, uint word, uint fallback) {
    uint value = fallback;
#define LIGHT_FLAT_PICK(k) value = uint(k) < kLightFlatCount && leaf == uint(k) ? (word == 12u ? kLightFlat##k##_12 : (word == 13u ? kLightFlat##k##_13 : kLightFlat##k##_14)) : value;
    LIGHT_FLAT_EACH(LIGHT_FLAT_PICK)
#undef LIGHT_FLAT_PICK
    return value;
}
uint lightFlatLight(uint leaf) { return lightFlatWord(leaf, 12u, 0u); }
uint lightFlatPrimitive(uint leaf) { return lightFlatWord(leaf, 13u, NO_HIT); }
uint lightFlatHitPrimitive(uint leaf) { return lightFlatWord(leaf, 14u, NO_HIT); }
uint lightFlatLeafHitBy(uint primitive) {
    uint leaf = LIGHT_FLAT_MAX_LEAVES;
#define LIGHT_FLAT_PICK(k) leaf = uint(k) < kLightFlatCount && kLightFlat##k##_14 == primitive ? uint(k) : leaf;
    LIGHT_FLAT_EACH(LIGHT_FLAT_PICK)
#undef LIGHT_FLAT_PICK
    return leaf;
}

#endif
