// Owen-scrambled Sobol' points, "padded" two dimensions at a time (Burley 2020, "Practical
// Hash-based Owen Scrambling", JCGT 9(4)). Only the bit manipulation lives here; which seeds
// a pixel and dimension pair get, and the conversion to floats, are rng.glsl's.
// The same construction is pbrt-v4's PaddedSobolSampler (src/pbrt/samplers.h) and Cycles'
// Sobol-Burley sampler (intern/cycles/kernel/sample/sobol_burley.h).
#ifndef PENUMBRA_SOBOL_GLSL
#define PENUMBRA_SOBOL_GLSL

// Laine-Karras style hash with Vegdahl's constants (N. Vegdahl 2021, "Building a Better LK
// Hash", psychopath.io/post/2021_01_30_building_a_better_lk_hash). Every step (xor with an
// even multiple, add, multiply by an odd number) is a bijection that leaves bit i as bit i
// xor a function of the seed and the bits below i: applied to a bit-reversed number it is
// a nested uniform scramble, i.e. an Owen scramble whose flips come from hashing `seed`.
uint laineKarrasPermutation(uint x, uint seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

// Owen scramble of a 32-bit fraction (bit 31 = 1/2): each bit is flipped or not as a
// function of the bits above it (Burley 2020). A scrambled point is uniform on
// [0,1), and any two points that share their first k bits still share them afterwards, so
// elementary intervals map onto elementary intervals and nets stay nets.
uint nestedUniformScramble(uint x, uint seed) {
    return bitfieldReverse(laineKarrasPermutation(bitfieldReverse(x), seed));
}

// Sobol' dimensions 0 and 1 of `index` as 32-bit fractions. Dimension 0 is the van der
// Corput sequence (bit reversal); dimension 1's direction numbers are v_k = v_{k-1} ^
// (v_{k-1} >> 1), v_0 = 1/2 (Burley 2020): the rows of Pascal's triangle mod 2, so by Lucas'
// theorem fraction bit i (from the top) is the XOR of the index bits k whose position k
// contains i bitwise (C(k, i) odd iff i & k == i). That sum over supersets of the 5-bit
// positions takes one shift-xor per position bit, instead of a loop over the index's 32
// bits (which llvmpipe runs to the longest lane's end); the result is the same bit for bit.
// Together they form a (0,2)-sequence in base 2: every aligned block of 2^m indices is a
// (0,m,2)-net.
uvec2 sobol2d(uint index) {
    uint z = index;
    z ^= (z & 0xaaaaaaaau) >> 1;
    z ^= (z & 0xccccccccu) >> 2;
    z ^= (z & 0xf0f0f0f0u) >> 4;
    z ^= (z & 0xff00ff00u) >> 8;
    z ^= (z & 0xffff0000u) >> 16;
    return uvec2(bitfieldReverse(index), bitfieldReverse(z));
}

// Point `index` of a 2D Sobol' sequence whose order is shuffled and whose coordinates are
// scrambled, with seeds.x for the shuffle and seeds.y, seeds.z for the two coordinates
// (Burley 2020). The shuffle is itself an Owen scramble of the
// index: it maps every aligned block of 2^m indices onto another aligned block, so the
// first 2^m samples (and every later aligned block) still form a (0,m,2)-net. Independent
// shuffles for each dimension pair decorrelate the pairs ("padding", Kollig & Keller 2002).
uvec2 shuffledScrambledSobol2d(uint index, uvec3 seeds) {
    uvec2 p = sobol2d(nestedUniformScramble(index, seeds.x));
    return uvec2(nestedUniformScramble(p.x, seeds.y), nestedUniformScramble(p.y, seeds.z));
}

#endif
