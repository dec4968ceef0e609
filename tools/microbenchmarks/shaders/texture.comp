// Texture lookups in a divergent dependent chain: each invocation starts at its own uv and
// takes the next uv from the texel it just read, so no lookup can be hoisted and the lanes
// of a SIMD group read scattered texels. TEX_IMAGE: a sampled image of its own (RGBA16F,
// linear filter, repeat) through textureLod; TEX_TEXEL: half texels in an RGBA32UI texel
// buffer, bilinear and repeat in the shader; otherwise the renderer's path
// (textures/textures.glsl): the texture inside a larger RGBA16F atlas image with a 1-texel
// gutter of its repeat neighbours, the uv wrapped in the shader, the atlas sampled at
// unnormalized coordinates. The same texture: each invocation's first lookup is written out
// (with the chain's sum, so that no lookup is optimized away) and compared between them.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/types.h"
layout(local_size_x = 64) in;

layout(std430, binding = 0) writeonly buffer Results { vec4 results[]; };
layout(push_constant) uniform Push {
    uint width;
    uint height;
    uint steps;
    uint atlasX;  // the atlas variant: the texture's texel (0, 0) is at (atlasX, 1) in the atlas
} push;

#ifdef TEX_IMAGE
layout(binding = BINDING_TEXTURE_ATLAS) uniform sampler2D image;
vec4 lookup(vec2 uv) { return textureLod(image, uv, 0.0); }
#elif defined(TEX_TEXEL)
// The renderer's texture path before the atlas: every texture's RGBA half texels, two per
// RGBA32UI texel, filtered and wrapped (repeat) in the shader.
layout(binding = BINDING_TEXTURE_ATLAS) uniform usamplerBuffer textureTexels;
vec4 fetchTexel(uint index) {
    uvec4 pair = texelFetch(textureTexels, int(index >> 1u));
    uvec2 halves = (index & 1u) == 0u ? pair.xy : pair.zw;
    return vec4(unpackHalf2x16(halves.x), unpackHalf2x16(halves.y));
}
void repeatAxis(float u, uint n, out uint i0, out uint i1, out float f) {
    float p = fract(u) * float(n) - 0.5;
    float cell = floor(p);
    f = p - cell;
    int c = int(cell);
    i0 = uint(c + int(n)) % n;
    i1 = uint(c + 1 + int(n)) % n;
}
vec4 lookup(vec2 uv) {
    uv = mix(vec2(0.0), uv, lessThan(abs(uv), vec2(1e30)));
    uint x0, x1, y0, y1, width = push.width;
    vec2 f;
    repeatAxis(uv.x, width, x0, x1, f.x);
    repeatAxis(uv.y, push.height, y0, y1, f.y);
    vec4 t00 = fetchTexel(y0 * width + x0), t10 = fetchTexel(y0 * width + x1);
    vec4 t01 = fetchTexel(y1 * width + x0), t11 = fetchTexel(y1 * width + x1);
    return mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
}
#else
// The renderer's path (textures/textures.glsl): the texture at (atlasX, 1) in the atlas.
#include "textures/textures.glsl"
vec4 lookup(vec2 uv) {
    return sampleTexture(push.atlasX | 1u << 16u, push.width, push.height, TEXTURE_WRAP_REPEAT, uv);
}
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
