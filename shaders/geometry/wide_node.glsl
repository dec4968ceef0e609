// Decoding a wide node's quantized child planes (shared/types.h, WideNode), shared by the
// traversal (geometry/bvh.glsl) and the traversal-step micro-benchmark
// (tools/bench/microbenchmarks/shaders/step.comp). host/bvh/wide.cpp decodes them with the same
// operations (decodeWideChild).
#ifndef PENUMBRA_WIDE_NODE_GLSL
#define PENUMBRA_WIDE_NODE_GLSL

// The four children's planes on one axis, given as ray distances: byte c of `words` is child
// c's q, its plane base + plane(E, q), where plane(E, q) is the float whose exponent field
// is E (`exponentBits` = E << 23) and whose mantissa holds q in bits 8-15: built from the
// bits, with no conversion of q and no multiply (docs/performance-history/round-19.md). Then
// (plane - origin) * invDir, in that order, as intersectBox computes a slab distance.
vec4 wideChildPlaneDistances(uint words, float base, uint exponentBits, float origin, float invDir) {
    uvec4 q = (uvec4(words) >> uvec4(0u, 8u, 16u, 24u)) & 0xffu;
    return (base + uintBitsToFloat(exponentBits | (q << 8u)) - origin) * invDir;
}

#endif
