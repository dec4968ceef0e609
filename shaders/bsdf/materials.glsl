// The scene's materials, read once per shading point. A texel buffer rather than a storage
// buffer: on llvmpipe (Mesa 22.3) a storage-buffer load after a branch becomes a loop over
// the SIMD lanes with bounds-check branches, a texel fetch a branch-free gather (see
// geometry/bvh.glsl and docs/performance-history/round-02.md).
#ifndef PENUMBRA_MATERIALS_GLSL
#define PENUMBRA_MATERIALS_GLSL

#include "shared/types.h"

// Material i is texels 2i (kd, type) and 2i + 1 (ks, exponent), RGBA32UI.
layout(binding = BINDING_MATERIALS) uniform usamplerBuffer materialTexels;

Material loadMaterial(uint index) {
    uvec4 a = texelFetch(materialTexels, int(MATERIAL_TEXELS * index));
    uvec4 b = texelFetch(materialTexels, int(MATERIAL_TEXELS * index + 1u));
    return Material(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), uintBitsToFloat(b.w));
}

#endif
