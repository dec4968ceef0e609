// Texture lookups in a divergent dependent chain: each invocation starts at its own uv and
// takes the next uv from the texel it just read, so no lookup can be hoisted and the lanes
// of a SIMD group read scattered texels. TEX_IMAGE: a sampled image (RGBA16F, linear
// filter, repeat) through textureLod; TEX_ATLAS: the texture inside a larger RGBA16F atlas
// image with a 1-texel gutter holding its repeat neighbours, the uv wrapped in the shader
// and the atlas sampled at unnormalized coordinates (linear filter, clamp to edge);
// otherwise half texels in an RGBA32UI texel buffer, bilinear and repeat in the shader
// (textures/textures.glsl). The same texture: each invocation's first lookup is written out
// (with the chain's sum, so that no lookup is optimized away) and compared between them.
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

layout(std430, binding = 0) writeonly buffer Results { vec4 results[]; };
layout(push_constant) uniform Push {
    uint width;
    uint height;
    uint steps;
    uint atlasX;  // TEX_ATLAS: the texture's texel (0, 0) is at (atlasX, 1) in the atlas
} push;

#ifdef TEX_IMAGE
layout(binding = BINDING_TEXTURE_TEXELS_IMAGE) uniform sampler2D image;
vec4 lookup(vec2 uv) { return textureLod(image, uv, 0.0); }
#elif defined(TEX_ATLAS)
layout(binding = BINDING_TEXTURE_TEXELS_IMAGE) uniform sampler2D atlas;
vec4 lookup(vec2 uv) {
    // Repeat: the continuous texel coordinate in [0, n]; the gutter supplies the wrapped
    // neighbour of the edge texels, so the sampler's footprint never needs wrapping.
    vec2 p = fract(uv) * vec2(push.width, push.height);
    return textureLod(atlas, p + vec2(push.atlasX, 1u), 0.0);
}
#else
#include "textures/textures.glsl"
vec4 lookup(vec2 uv) { return sampleTexture(0u, push.width, push.height, TEXTURE_WRAP_REPEAT, uv); }
#endif

uint hash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    return x ^ (x >> 16);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    vec2 uv = vec2(hash(i), hash(i ^ 0x9e3779b9u)) * (1.0 / 4294967296.0);
    vec4 first = lookup(uv);  // compared between the variants (the chain itself is chaotic)
    vec4 sum = vec4(0.0);
    for (uint s = 0u; s < push.steps; ++s) {
        vec4 t = lookup(uv);
        sum += t;
        // The next point depends on the texel read: a dependent, divergent chain.
        uv = fract(uv * 1.61803 + t.xy * 0.37 + 0.123);
    }
    results[i] = vec4(first.xyz, sum.x + sum.y + sum.z + sum.w);
}
