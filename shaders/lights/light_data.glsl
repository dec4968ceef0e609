// Where the light-sampling code reads its scene data: the lights, the alias tables, the
// environment map and the primitives of area lights. Every read in lights/ and the integrators goes through
// these functions, so that how the data is stored on the GPU (which buffer kind, which
// layout) is decided in this file alone.
#ifndef PENUMBRA_LIGHT_DATA_GLSL
#define PENUMBRA_LIGHT_DATA_GLSL

#include "shared/types.h"
#include "geometry/bvh.glsl"

// Texel buffers (RGBA32UI views of the same bytes as the structs, host/gpu/kernel.cpp)
// rather than storage buffers: llvmpipe (Mesa 22.3) turns a storage-buffer load after a
// branch into a loop over the SIMD lanes with bounds-check branches, a texel fetch into a
// branch-free gather (the same change for nodes, primitives and materials bought
// 1.5-1.9x: docs/performance-history/round-02.md). Light i is texels 3i (type, first, count,
// flags), 3i + 1 (emission, area), 3i + 2 (position, selectionProb); alias entry i is
// texel i.
layout(binding = BINDING_LIGHTS) uniform usamplerBuffer lightTexels;
layout(binding = BINDING_LIGHT_TABLE) uniform usamplerBuffer lightTableTexels;
layout(binding = BINDING_MESH_TABLE) uniform usamplerBuffer meshTableTexels;
// The environment map: texel i is (radiance RGB, 0), entry i of its alias table is texel i.
layout(binding = BINDING_ENV_TEXELS) uniform usamplerBuffer environmentTexels;
layout(binding = BINDING_ENV_TABLE) uniform usamplerBuffer environmentTableTexels;

Light loadLight(uint index) {
    uvec4 a = texelFetch(lightTexels, int(LIGHT_TEXELS * index));
    uvec4 b = texelFetch(lightTexels, int(LIGHT_TEXELS * index + 1u));
    uvec4 c = texelFetch(lightTexels, int(LIGHT_TEXELS * index + 2u));
    return Light(a.x, a.y, a.z, a.w, uintBitsToFloat(b.xyz), uintBitsToFloat(b.w), uintBitsToFloat(c.xyz),
                 uintBitsToFloat(c.w));
}

AliasEntry aliasEntry(uvec4 texel) {
    return AliasEntry(uintBitsToFloat(texel.x), texel.y, texel.z, uintBitsToFloat(texel.w));
}

// Entry `index` of the light-selection table (host/render/alias_table.h).
AliasEntry loadLightAlias(uint index) { return aliasEntry(texelFetch(lightTableTexels, int(index))); }

// Entry `index` of the per-mesh triangle tables (area-proportional, lecture "Mesh Lights").
AliasEntry loadMeshAlias(uint index) { return aliasEntry(texelFetch(meshTableTexels, int(index))); }

// Radiance of environment-map texel `index` (row-major from the top row).
vec3 loadEnvironmentTexel(uint index) { return uintBitsToFloat(texelFetch(environmentTexels, int(index)).xyz); }

// Entry `index` of the environment map's alias table (item = texel index).
AliasEntry loadEnvironmentAlias(uint index) { return aliasEntry(texelFetch(environmentTableTexels, int(index))); }

// The primitive (sphere, quad or triangle) of an area light: the traversal's texel view.
Primitive loadLightPrimitive(uint index) { return loadPrimitive(index); }

#endif
