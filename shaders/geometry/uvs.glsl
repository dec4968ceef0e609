// The per-primitive texture coordinates buffer (shared/types.h, TriangleUvs), declared once
// for the surface point (geometry/surface.glsl) and the alpha test (textures/alpha_mask.glsl),
// which traversal runs before any surface point exists.
#ifndef PENUMBRA_UVS_GLSL
#define PENUMBRA_UVS_GLSL

#include "shared/types.h"

// Per-vertex texture coordinates of every primitive (leaf order; zero for meshes without
// `uvs`, unused for quads and spheres). Bound and read only when the scene is textured.
layout(std430, binding = BINDING_UVS) readonly restrict buffer TriangleUvsBuffer { TriangleUvs uvs[]; };

#endif
