// Material textures (SCENE_FORMAT.md "Textures (v2)"): applyTextures replaces each textured
// value slot of a Material by scale x texture(u, v), clamped to [0, 1], once per shading
// point, before any BRDF code sees the material. Bilinear filtering with repeat wrapping (or
// a glTF sampler's clamp or mirror) on texels stored as half floats in one texel buffer
// (layout: shared/types.h, "Textures"), after each reference's uv transform, if the scene
// has any (glTF KHR_texture_transform).
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

// One axis of a bilinear lookup over n texels: the two texel indices to blend and the
// weight of the second. Texel i covers [i, i+1)/n with its centre at (i + 0.5)/n; between
// centres the two nearest texels are blended by distance (pbrt-v4 Image::Bilerp, section
// 10.4.3). Outside [0, 1] the texture repeats, mirrors (every other copy flipped, so that
// a texel meets its own copy at each integer u) or clamps to its edge texels (glTF 2.0
// section 5.26, samplers).
void wrapAxis(float u, uint n, uint wrap, out uint i0, out uint i1, out float f) {
    float t = u;
    if (wrap == TEXTURE_WRAP_REPEAT) t = fract(u);
    else if (wrap == TEXTURE_WRAP_MIRROR) t = 1.0 - abs(u - 2.0 * floor(0.5 * u) - 1.0);
    else t = clamp(u, -1.0, 2.0);  // beyond one texture width every lookup is the edge texel
    float p = t * float(n) - 0.5;
    float cell = floor(p);
    f = p - cell;
    int c = int(cell);  // in [-1, n - 1] for repeat and mirror, [-n - 1, 2n - 1] for clamp
    if (wrap == TEXTURE_WRAP_REPEAT) {
        // Adding n keeps the modulo non-negative.
        i0 = uint(c + int(n)) % n;
        i1 = uint(c + 1 + int(n)) % n;
    } else {
        // Mirror: the texel beyond an edge is the edge texel's mirror image, itself.
        i0 = uint(clamp(c, 0, int(n) - 1));
        i1 = uint(clamp(c + 1, 0, int(n) - 1));
    }
}

// Bilinear lookup with wrapping `wrap` (TEXTURE_WRAP_* along u | along v << 2); row j = 0
// is at v = 0 (the top of the image).
vec4 sampleTexture(uint firstTexel, uint width, uint height, uint wrap, vec2 uv) {
    // Non-finite coordinates (a degenerate triangle's interpolation) read texel (0, 0)
    // instead of an undefined address.
    uv = mix(vec2(0.0), uv, lessThan(abs(uv), vec2(1e30)));
    uint x0, x1, y0, y1;
    vec2 f;
    wrapAxis(uv.x, width, wrap & 3u, x0, x1, f.x);
    wrapAxis(uv.y, height, (wrap >> 2u) & 3u, y0, y1, f.y);
    vec4 t00 = fetchTexel(firstTexel + y0 * width + x0), t10 = fetchTexel(firstTexel + y0 * width + x1);
    vec4 t01 = fetchTexel(firstTexel + y1 * width + x0), t11 = fetchTexel(firstTexel + y1 * width + x1);
    return mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
}

// `m` (material `materialIndex` as bsdf/materials.glsl loaded it) with its textured slots
// replaced by their values at `uv`. Values are clamped to [0, 1], the range of every
// texturable field; a textured Phong material keeps kd + ks <= 1 (the contract's rule for
// its values) by lowering ks, so that no texture can make it reflect more than it receives.
// Texels from one reference to the next: a transformed scene's carry their TextureTransform.
uint textureRefStride() {
    return hasTextureTransforms() ? TEXTURE_REF_TEXELS + TEXTURE_TRANSFORM_TEXELS : TEXTURE_REF_TEXELS;
}

// The coordinates reference `ref` looks up at `uv`: its TextureTransform applied (the host
// wrote KHR_texture_transform's T R S as two rows, render/texture_arrays.cpp), or uv itself
// in scenes without transforms.
vec2 transformedUv(int ref, vec2 uv) {
    if (!hasTextureTransforms()) return uv;
    vec3 p = vec3(uv, 1.0);
    vec3 u = uintBitsToFloat(texelFetch(materialTextureTexels, ref + int(TEXTURE_REF_TEXELS)).xyz);
    vec3 v = uintBitsToFloat(texelFetch(materialTextureTexels, ref + int(TEXTURE_REF_TEXELS) + 1).xyz);
    return vec2(dot(u, p), dot(v, p));
}

Material applyTextures(Material m, uint materialIndex, vec2 uv) {
    if (!hasTextures()) return m;
    uvec4 header = texelFetch(materialTextureTexels, int(materialIndex));
    for (uint i = 0u; i < header.y; ++i) {
        int ref = int(header.x + textureRefStride() * i);
        uvec4 a = texelFetch(materialTextureTexels, ref);
        uvec4 b = texelFetch(materialTextureTexels, ref + 1);
        vec4 t = sampleTexture(b.x, b.y, b.z, b.w, transformedUv(ref, uv));
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

// What material `materialIndex`'s emission texture (TEXTURE_SLOT_EMISSION) scales emitted
// radiance by at `uv`: scale x texture, clamped to [0, 1] (the Light's emission is
// emissiveFactor x strength, the most the surface emits), or 1 where the material has none.
// Emission and light sampling call it at the same point with the same uv, so the radiance a
// light sample carries is the radiance a BRDF-sampled ray would find there.
vec3 emissionTexture(uint materialIndex, vec2 uv) {
    if (!hasEmissionTextures()) return vec3(1.0);
    uvec4 header = texelFetch(materialTextureTexels, int(materialIndex));
    for (uint i = 0u; i < header.y; ++i) {
        int ref = int(header.x + textureRefStride() * i);
        uvec4 a = texelFetch(materialTextureTexels, ref);
        if ((a.w & 0xffu) != TEXTURE_SLOT_EMISSION) continue;
        uvec4 b = texelFetch(materialTextureTexels, ref + 1);
        vec4 t = sampleTexture(b.x, b.y, b.z, b.w, transformedUv(ref, uv));
        return clamp(uintBitsToFloat(a.xyz) * t.rgb, 0.0, 1.0);
    }
    return vec3(1.0);
}

#endif
