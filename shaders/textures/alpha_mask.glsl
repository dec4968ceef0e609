// glTF alphaMode MASK (glTF 2.0 section 3.9.4): a triangle point whose alpha, baseColorFactor.a
// x the base colour texture's alpha, is below alphaCutoff is no surface: camera, BRDF-sampled
// and shadow rays all go through it, because the test sits in the traversal's triangle hit
// (geometry/bvh.glsl, testPrimitive and tracePair). Kernels include this file before
// bvh.glsl to get the test; others (the shader tests) trace without it. The host resolves
// materials whose alpha is a constant (opaque or entirely cut out), so only textured alpha
// reaches here (host/scene/load_gltf.cpp).
#ifndef PENUMBRA_ALPHA_MASK_GLSL
#define PENUMBRA_ALPHA_MASK_GLSL

#include "shared/types.h"
#include "common/specialization.glsl"
#include "geometry/uvs.glsl"
#include "textures/textures.glsl"

// Whether the hit at barycentric (u, v) = `bary` of primitive `index` (p) is cut out.
bool alphaCutOut(uint index, Primitive p, vec2 bary) {
    if (!hasAlphaMask() || (p.typeAndNormals & PRIM_TYPE_MASK) != PRIM_TRIANGLE) return false;
    uvec4 header = texelFetch(materialTextureTexels, int(p.material));
    for (uint i = 0u; i < header.y; ++i) {
        int ref = int(header.x + textureRefStride() * i);
        uvec4 a = texelFetch(materialTextureTexels, ref);
        if ((a.w & 0xffu) != TEXTURE_SLOT_ALPHA) continue;
        uvec4 b = texelFetch(materialTextureTexels, ref + 1);
        TriangleUvs t = uvs[index];
        vec2 uv = (1.0 - bary.x - bary.y) * t.uv01.xy + bary.x * t.uv01.zw + bary.y * t.uv2.xy;
        vec2 scaleCutoff = uintBitsToFloat(a.xy);
        return scaleCutoff.x * sampleTexture(b.x, b.y, b.z, b.w, transformedUv(ref, uv)).a < scaleCutoff.y;
    }
    return false;
}

#endif
