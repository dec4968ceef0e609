// The light BVH of `light_selection: "bvh"` on the GPU (host/render/light_bvh.h builds it;
// Conty Estevez and Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree
// Splitting"; pbrt-v4's BVHLightSampler, PBR book 4th ed. section 12.6.3). From the root,
// each interior node's two children are weighted by lightBvhImportance, a bound on what
// the lights below can contribute at the shading point (power, distance, the emission
// cone, the shading normal's hemisphere), and one is taken in proportion; the product of
// those ratios is the probability of the item reached. For MIS, lightBvhTreePmf replays
// an item's stored trail (one bit per level) from the root and multiplies the same ratios
// again, so the probability of a light hit by a BRDF-sampled ray is exactly the one it
// would have been sampled with.
//
// Every formula here mirrors host/render/light_bvh.cpp line for line (same operations in
// the same order), so that tests/test_light_bvh_gpu.cpp can compare the GPU's choices and
// probabilities with the host's.
#ifndef PENUMBRA_LIGHT_BVH_GLSL
#define PENUMBRA_LIGHT_BVH_GLSL

#include "shared/types.h"
#include "shared/light_bvh.h"
#include "lights/light_importance.glsl"

// RGBA32UI texels (render/light_bvh_arrays.h): node i is texels 3i .. 3i + 2, then the
// items and the per-primitive trails at the offsets the caller passes.
layout(binding = BINDING_LIGHT_BVH) uniform usamplerBuffer lightBvhTexels;

LightBvhNode loadLightBvhNode(uint index) {
    uvec4 a = texelFetch(lightBvhTexels, int(3u * index));
    uvec4 b = texelFetch(lightBvhTexels, int(3u * index + 1u));
    uvec4 c = texelFetch(lightBvhTexels, int(3u * index + 2u));
    return LightBvhNode(uintBitsToFloat(a.xyz), uintBitsToFloat(a.w), uintBitsToFloat(b.xyz), b.w,
                        uintBitsToFloat(c.xyz), c.w);
}

LightBvhItem loadLightBvhItem(uint itemsTexel, uint item) {
    uvec4 t = texelFetch(lightBvhTexels, int(itemsTexel + item));
    return LightBvhItem(t.x, t.y, t.z, t.w);
}

// The trail of the item that stands for primitive `primitive` (leaf order): two per texel.
uvec2 loadLightBvhTrail(uint trailsTexel, uint primitive) {
    uvec4 t = texelFetch(lightBvhTexels, int(trailsTexel + primitive / 2u));
    return (primitive & 1u) == 0u ? t.xy : t.zw;
}

// The 16-bit cosines (shared/light_bvh.h), as light_bvh.cpp's decodeCos.
float lightBvhDecodeCos(uint q) { return float(q) / 65535.0 * 2.0 - 1.0; }

// What lightImportance needs of a node, as light_bvh.cpp's lightBvhImportanceTerms.
LightImportanceTerms lightBvhImportanceTerms(LightBvhNode node) {
    float cosThetaO = lightBvhDecodeCos(node.cosines & 0xffffu);
    float halfDiagonal = 0.5 * length(node.boundsMax - node.boundsMin);
    return LightImportanceTerms((node.boundsMin + node.boundsMax) * 0.5, halfDiagonal * halfDiagonal, node.axis,
                                node.power, cosThetaO, lightBvhSafeSqrt(1.0 - cosThetaO * cosThetaO),
                                lightBvhDecodeCos(node.cosines >> 16u),
                                (node.childOrItem & LIGHT_BVH_TWO_SIDED) != 0u ? 1u : 0u);
}

// Importance of a node at p with shading normal n (lights/light_importance.glsl).
float lightBvhImportance(LightBvhNode node, vec3 p, vec3 n) {
    return lightImportance(lightBvhImportanceTerms(node), p, n);
}

// The weights of an interior node's children (first = the next node, second): their
// importances, or their powers where both bounds are zero (light_bvh.cpp, childWeights,
// says why every item keeps a probability).
void lightBvhChildWeights(LightBvhNode first, LightBvhNode second, vec3 p, vec3 n, out float c0, out float c1) {
    c0 = lightBvhImportance(first, p, n);
    c1 = lightBvhImportance(second, p, n);
    if (!(c0 + c1 > 0.0)) {
        c0 = first.power;
        c1 = second.power;
    }
}

// Trails have 64 bits, one per level: no path is longer.
const uint LIGHT_BVH_MAX_DEPTH = 64u;

// Descends from the root with one uniform number u in [0, 1), rescaled at each level
// (pbrt-v4), as sampleLightBvh: the item reached (its index), its probability `pmf` in the
// tree, and in `rest` what is left of u. The tree must have a node.
uint sampleLightBvhTree(vec3 p, vec3 n, float u, out float pmf, out float rest) {
    const float oneMinusEpsilon = uintBitsToFloat(0x3f7fffffu);
    uint index = 0u;
    LightBvhNode node = loadLightBvhNode(0u);
    pmf = 1.0;
    rest = u;
    for (uint depth = 0u; depth <= LIGHT_BVH_MAX_DEPTH; ++depth) {
        if ((node.childOrItem & LIGHT_BVH_LEAF) != 0u) {
            rest = u;
            return node.childOrItem & LIGHT_BVH_INDEX_MASK;
        }
        uint second = node.childOrItem & LIGHT_BVH_INDEX_MASK;
        LightBvhNode n0 = loadLightBvhNode(index + 1u), n1 = loadLightBvhNode(second);
        float c0, c1;
        lightBvhChildWeights(n0, n1, p, n, c0, c1);
        float p0 = c0 / (c0 + c1);
        // The same expression as lightBvhTreePmf's, so that sampled and replayed pmfs agree exactly.
        if (u < p0) {
            pmf *= c0 / (c0 + c1);
            u = min(u / p0, oneMinusEpsilon);
            index = index + 1u;
            node = n0;
        } else {
            pmf *= c1 / (c0 + c1);
            u = min((u - p0) / (1.0 - p0), oneMinusEpsilon);
            index = second;
            node = n1;
        }
    }
    pmf = 0.0;
    return 0u;
}

// The probability that sampleLightBvhTree at (p, n) reaches the item whose trail this is.
float lightBvhTreePmf(vec3 p, vec3 n, uvec2 trail) {
    uint index = 0u;
    LightBvhNode node = loadLightBvhNode(0u);
    float pmf = 1.0;
    for (uint depth = 0u; depth <= LIGHT_BVH_MAX_DEPTH; ++depth) {
        if ((node.childOrItem & LIGHT_BVH_LEAF) != 0u) return pmf;
        uint second = node.childOrItem & LIGHT_BVH_INDEX_MASK;
        LightBvhNode n0 = loadLightBvhNode(index + 1u), n1 = loadLightBvhNode(second);
        float c0, c1;
        lightBvhChildWeights(n0, n1, p, n, c0, c1);
        bool right = (trail.x & 1u) != 0u;
        pmf *= (right ? c1 : c0) / (c0 + c1);
        index = right ? second : index + 1u;
        node = right ? n1 : n0;
        trail = uvec2((trail.x >> 1u) | (trail.y << 31u), trail.y >> 1u);
    }
    return 0.0;
}

#endif
