// Material textures (SCENE_FORMAT.md "Textures (v2)"): applyTextures replaces each textured
// value slot of a Material by scale x texture(u, v), clamped to [0, 1], once per shading
// point, before any BRDF code sees the material. Bilinear filtering with repeat wrapping on
// texels stored as half floats in one texel buffer (layout: shared/types.h, "Textures").
#ifndef PENUMBRA_TEXTURES_GLSL
#define PENUMBRA_TEXTURES_GLSL

#include "shared/types.h"
#include "common/specialization.glsl"

// Per material: (first reference, count); then the TextureRefs (two texels each).
layout(binding = BINDING_MATERIAL_TEXTURES) uniform usamplerBuffer materialTextureTexels;
// Every texture's texels, two RGBA half-float texels per RGBA32UI buffer texel.
layout(binding = BINDING_TEXTURE_TEXELS) uniform usamplerBuffer textureTexels;

// Texel `index` (counted over all textures) as linear RGBA.
vec4 fetchTexel(uint index) {
    uvec4 pair = texelFetch(textureTexels, int(index >> 1u));
    uvec2 halves = (index & 1u) == 0u ? pair.xy : pair.zw;
    return vec4(unpackHalf2x16(halves.x), unpackHalf2x16(halves.y));
}

// Bilinear lookup with repeat wrapping. Texel (i, j) covers [i, i+1)/W x [j, j+1)/H of the
// unit square with its centre at ((i + 0.5)/W, (j + 0.5)/H), row j = 0 at v = 0 (the top
// of the image); between centres the four nearest texels are blended by distance (pbrt-v4
// Image::Bilerp, section 10.4.3). Only the fractional part of u and v matters (repeat).
vec4 sampleTexture(uint firstTexel, uint width, uint height, vec2 uv) {
    // Non-finite coordinates (a degenerate triangle's interpolation) read texel (0, 0)
    // instead of an undefined address.
    uv = mix(vec2(0.0), uv, lessThan(abs(uv), vec2(1e30)));
    vec2 size = vec2(width, height);
    vec2 p = fract(uv) * size - 0.5;
    vec2 cell = floor(p);
    vec2 f = p - cell;
    // cell is in [-1, size - 1]: adding size keeps the modulo non-negative.
    ivec2 c0 = ivec2(cell) + ivec2(width, height);
    uint x0 = uint(c0.x) % width, x1 = (uint(c0.x) + 1u) % width;
    uint y0 = uint(c0.y) % height, y1 = (uint(c0.y) + 1u) % height;
    vec4 t00 = fetchTexel(firstTexel + y0 * width + x0), t10 = fetchTexel(firstTexel + y0 * width + x1);
    vec4 t01 = fetchTexel(firstTexel + y1 * width + x0), t11 = fetchTexel(firstTexel + y1 * width + x1);
    return mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
}

// `m` (material `materialIndex` as bsdf/materials.glsl loaded it) with its textured slots
// replaced by their values at `uv`. Values are clamped to [0, 1], the range of every
// texturable field; a textured Phong material keeps kd + ks <= 1 (the contract's rule for
// its values) by lowering ks, so that no texture can make it reflect more than it receives.
Material applyTextures(Material m, uint materialIndex, vec2 uv) {
    if (!hasTextures()) return m;
    uvec4 header = texelFetch(materialTextureTexels, int(materialIndex));
    for (uint i = 0u; i < header.y; ++i) {
        int ref = int(header.x + TEXTURE_REF_TEXELS * i);
        uvec4 a = texelFetch(materialTextureTexels, ref);
        uvec4 b = texelFetch(materialTextureTexels, ref + 1);
        vec4 t = sampleTexture(b.x, b.y, b.z, uv);
        vec3 scale = uintBitsToFloat(a.xyz);
        uint slot = a.w & 0xffu;
        float channel = t[min(a.w >> 8u, 3u)];
        if (slot == TEXTURE_SLOT_KD) m.kd = clamp(scale * t.rgb, 0.0, 1.0);
        else if (slot == TEXTURE_SLOT_KS) m.ks = clamp(scale * t.rgb, 0.0, 1.0);
        else if (slot == TEXTURE_SLOT_KS_X) m.ks.x = clamp(scale.x * channel, 0.0, 1.0);
        else if (slot == TEXTURE_SLOT_KS_Y) m.ks.y = clamp(scale.x * channel, 0.0, 1.0);
    }
    if (header.y != 0u && m.type == MATERIAL_PHONG) m.ks = min(m.ks, 1.0 - m.kd);
    return m;
}

#endif
