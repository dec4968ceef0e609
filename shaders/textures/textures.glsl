// Material textures (SCENE_FORMAT.md "Textures (v2)"): applyTextures replaces each textured
// value slot of a Material by scale x texture(u, v), clamped to [0, 1], once per shading
// point, before any BRDF code sees the material. Bilinear filtering with repeat wrapping (or
// a glTF sampler's clamp or mirror): the shader wraps, the sampler filters, in one atlas
// image of every texture (layout: shared/types.h, "Textures"; docs/PERFORMANCE.md, why).
#ifndef PENUMBRA_TEXTURES_GLSL
#define PENUMBRA_TEXTURES_GLSL

#include "shared/types.h"
#include "common/specialization.glsl"

// Per material: (first reference, count); then the TextureRefs (two texels each).
layout(binding = BINDING_MATERIAL_TEXTURES) uniform usamplerBuffer materialTextureTexels;
// Every texture, each inside a 1-texel gutter of its repeat neighbours; the sampler takes
// unnormalized coordinates (texels) and filters linearly.
layout(binding = BINDING_TEXTURE_ATLAS) uniform sampler2D textureAtlas;

// One axis of a lookup over n texels: the continuous texel coordinate, in [0, n], at which
// the texture is filtered. Texel i covers [i, i+1)/n with its centre at (i + 0.5)/n; the
// sampler blends the two nearest centres by distance (Vulkan spec, "Texel Filtering"; the
// same as pbrt-v4 Image::Bilerp, section 10.4.3). Outside [0, 1] the texture repeats,
// mirrors (every other copy flipped, so that a texel meets its own copy at each integer u)
// or clamps to its edge texels (glTF 2.0 section 5.26, samplers). Repeat reads the gutter
// within half a texel of an edge, which holds the opposite edge; clamp and mirror stop at
// the edge texels' centres, where the gutter's weight is 0.
float wrapAxis(float u, uint n, uint wrap) {
    float size = float(n);
    if (wrap == TEXTURE_WRAP_REPEAT) return fract(u) * size;
    float t = wrap == TEXTURE_WRAP_MIRROR ? 1.0 - abs(u - 2.0 * floor(0.5 * u) - 1.0) : clamp(u, 0.0, 1.0);
    return clamp(t * size, 0.5, size - 0.5);
}

// Bilinear lookup with wrapping `wrap` (TEXTURE_WRAP_* along u | along v << 2) of the
// width x height texture whose texel (0, 0) is at atlas texel `origin` (x | y << 16);
// row j = 0 is at v = 0 (the top of the image).
vec4 sampleTexture(uint origin, uint width, uint height, uint wrap, vec2 uv) {
    // Non-finite coordinates (a degenerate triangle's interpolation) read at uv (0, 0)
    // instead of an undefined address.
    uv = mix(vec2(0.0), uv, lessThan(abs(uv), vec2(1e30)));
    vec2 texel = vec2(wrapAxis(uv.x, width, wrap & 3u), wrapAxis(uv.y, height, (wrap >> 2u) & 3u));
    // Explicit LOD 0: unnormalized coordinates allow no other (and there is one level).
    return textureLod(textureAtlas, vec2(origin & 0xffffu, origin >> 16u) + texel, 0.0);
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
        vec4 t = sampleTexture(b.x, b.y, b.z, b.w, uv);
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
