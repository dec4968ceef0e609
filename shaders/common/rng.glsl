// Stateless random numbers: every value is a hash of (pixel, sample index, seed,
// dimension), so a pixel's estimate depends only on those (SCENE_FORMAT.md) and renders
// split into disjoint sample ranges merge exactly. Hash: pcg4d from Jarzynski & Olano
// 2020, "Hash Functions for GPU Rendering", JCGT 9(3).
#ifndef PENUMBRA_RNG_GLSL
#define PENUMBRA_RNG_GLSL

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
};

Rng makeRng(uint pixel, uint sampleIndex, uint seed) { return Rng(pixel, sampleIndex, seed, 0u); }

// 24 random bits -> [0, 1): exactly representable, never 1.
float bitsToUnit(uint bits) { return float(bits >> 8) * (1.0 / 16777216.0); }

// Two independent uniform numbers in [0, 1)^2 for the next dimension pair.
vec2 rand2(inout Rng rng) {
    uvec4 h = pcg4d(uvec4(rng.pixel, rng.sampleIndex, rng.seed, rng.dimension));
    rng.dimension += 1u;
    return vec2(bitsToUnit(h.x), bitsToUnit(h.y));
}

float rand1(inout Rng rng) { return rand2(rng).x; }

#endif
