// Tangent-space normal maps (glTF 2.0 section 3.9.3, normalTexture): the shading normal of a
// surface point bent by its material's normal map, before anything shades with it. Included
// after textures/textures.glsl and geometry/surface.glsl.
//
// What follows from the bent normal is the rule every shading normal has here (geometry/
// surface.glsl, viewerSideNormals; integrators/direct.comp, cosineWeighted): where the bent
// normal faces away from the viewer the geometric normal shades instead (no black pixels),
// and light counts only from directions above both the shading and the geometric surface (no
// light leaking through it). That is pbrt-v4's shading-normal convention with a guard on the
// viewer's side; Cycles instead bends such a normal towards the viewer (ensure_valid_reflection).
#ifndef PENUMBRA_NORMAL_MAP_GLSL
#define PENUMBRA_NORMAL_MAP_GLSL

#include "shared/types.h"
#include "common/specialization.glsl"

// sp's shading normal bent by material sp.material's normal map (TEXTURE_SLOT_NORMAL), or
// sp.shadingNormal where it has none. The texel's rgb decodes to c = (2 rgb - 1) (scale,
// scale, 1), and the normal is normalize(c.x T + c.y B + c.z N) with N the interpolated
// vertex normal, T the interpolated tangent made orthogonal to N (Gram-Schmidt) and
// B = w cross(N, T) (glTF 2.0 sections 3.7.2.1 and 3.9.3). Without a frame (no tangent, or one
// along N) or without a direction (a texel that decodes to 0) it keeps N: never NaN.
vec3 normalMapped(SurfacePoint sp) {
    if (!hasNormalMaps()) return sp.shadingNormal;
    uvec4 header = texelFetch(materialTextureTexels, int(sp.material));
    for (uint i = 0u; i < header.y; ++i) {
        int ref = int(header.x + textureRefStride() * i);
        uvec4 a = texelFetch(materialTextureTexels, ref);
        if ((a.w & 0xffu) != TEXTURE_SLOT_NORMAL) continue;
        uvec4 b = texelFetch(materialTextureTexels, ref + 1);
        vec3 rgb = sampleTexture(b.x, b.y, b.z, b.w, transformedUv(ref, sp.uv)).rgb;
        vec3 c = vec3((2.0 * rgb.xy - 1.0) * uintBitsToFloat(a.x), 2.0 * rgb.z - 1.0);
        vec3 n = sp.shadingNormal;
        vec3 t = sp.tangent.xyz - n * dot(n, sp.tangent.xyz);
        float t2 = dot(t, t);
        if (!(t2 > 1e-20)) return n;
        t *= inversesqrt(t2);
        vec3 bitangent = (sp.tangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t);
        vec3 m = c.x * t + c.y * bitangent + c.z * n;
        float m2 = dot(m, m);
        return m2 > 1e-20 && m2 < 1e30 ? m * inversesqrt(m2) : n;
    }
    return sp.shadingNormal;
}

#endif
