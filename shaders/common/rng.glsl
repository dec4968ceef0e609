// Stateless random numbers: every value is a function of (pixel, sample index, seed,
// dimension), so a pixel's estimate depends only on those (SCENE_FORMAT.md) and renders
// split into disjoint sample ranges merge exactly. Two samplers share that interface:
// independent hashes (pcg4d from Jarzynski & Olano 2020, "Hash Functions for GPU
// Rendering", JCGT 9(3)) and padded Owen-scrambled Sobol' points (common/sobol.glsl).
#ifndef PENUMBRA_RNG_GLSL
#define PENUMBRA_RNG_GLSL

#include "shared/types.h"
#include "common/sobol.glsl"

uvec4 pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    return v;
}

struct Rng {
    uint pixel;
    uint sampleIndex;  // absolute: sample_offset + i
    uint seed;
    uint dimension;    // advanced by every draw
    uint samplerType;  // SAMPLER_* (shared/types.h); "sampler" is a GLSL keyword
};

Rng makeRng(uint pixel, uint sampleIndex, uint seed, uint samplerType) {
    return Rng(pixel, sampleIndex, seed, 0u, samplerType);
}
// Independent samples: what the warp, light and BSDF sampling tests need, since their
// chi-square statistics assume independent draws.
Rng makeRng(uint pixel, uint sampleIndex, uint seed) { return makeRng(pixel, sampleIndex, seed, SAMPLER_INDEPENDENT); }

// 24 random bits -> [0, 1): exactly representable, never 1.
float bitsToUnit(uint bits) { return float(bits >> 8) * (1.0 / 16777216.0); }

// Fourth input of the Sobol' seed hash: its seeds belong to a (pixel, seed, dimension), not
// to a sample index, so that slot holds a fixed tag.
const uint SOBOL_SEED_TAG = 0x50b01u;

// The next dimension pair as two 32-bit fractions (rand2Bits: for draws that need more
// than a float's 24 bits, such as a choice whose rest is used again, lights/alias.glsl), or
// uniform on [0, 1)^2 (rand2).
// Independent: a hash of (pixel, sample index, seed, dimension); pairs and samples are
// independent.
// Sobol: point `sampleIndex` of a 2D Owen-scrambled Sobol' sequence of its own for every
// (pixel, seed, dimension), the shuffle and scramble seeds hashed from those with pcg4d
// (Burley 2020's padding, as pbrt-v4's PaddedSobolSampler and Cycles' Sobol-Burley). Each
// point is still uniform (unbiased estimates), a pixel's first 2^m samples are a (0,m,2)-net
// in every pair, and pixels and pairs are decorrelated by their independent seeds.
// The render kernels pass the specialization constant kSampler, which compiles the other
// sampler out; the sampler tests pass it per dispatch.
uvec2 rand2Bits(inout Rng rng) {
    uvec2 bits;
    if (rng.samplerType == SAMPLER_SOBOL) {
        uvec3 seeds = pcg4d(uvec4(rng.pixel, rng.seed, rng.dimension, SOBOL_SEED_TAG)).xyz;
        bits = shuffledScrambledSobol2d(rng.sampleIndex, seeds);
    } else {
        bits = pcg4d(uvec4(rng.pixel, rng.sampleIndex, rng.seed, rng.dimension)).xy;
    }
    rng.dimension += 1u;
    return bits;
}

vec2 rand2(inout Rng rng) {
    uvec2 bits = rand2Bits(rng);
    return vec2(bitsToUnit(bits.x), bitsToUnit(bits.y));
}

float rand1(inout Rng rng) { return rand2(rng).x; }

#endif
