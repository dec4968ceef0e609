// Where the light-sampling code reads its scene data: the lights, the two alias tables and
// the primitives of area lights. Every read in lights/ and the integrators goes through
// these functions, so that how the data is stored on the GPU (which buffer kind, which
// layout) is decided in this file alone.
#ifndef PENUMBRA_LIGHT_DATA_GLSL
#define PENUMBRA_LIGHT_DATA_GLSL

#include "shared/types.h"
#include "geometry/bvh.glsl"

layout(std430, binding = BINDING_LIGHTS) readonly restrict buffer Lights { Light lights[]; };
layout(std430, binding = BINDING_LIGHT_TABLE) readonly restrict buffer LightTable { AliasEntry lightTable[]; };
layout(std430, binding = BINDING_MESH_TABLE) readonly restrict buffer MeshTable { AliasEntry meshTable[]; };

Light loadLight(uint index) { return lights[index]; }

// Entry `index` of the light-selection table (host/render/alias_table.h).
AliasEntry loadLightAlias(uint index) { return lightTable[index]; }

// Entry `index` of the per-mesh triangle tables (area-proportional, lecture "Mesh Lights").
AliasEntry loadMeshAlias(uint index) { return meshTable[index]; }

// The primitive (sphere, quad or triangle) of an area light.
Primitive loadLightPrimitive(uint index) { return primitives[index]; }

#endif
