// The ambient-occlusion kernel for scenes of at most 16 primitives, all inline
// (geometry/inline_geometry.glsl; the host picks it where render/inline_geometry.h's rule
// holds); the code is in integrators/ao.glsl.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PENUMBRA_INLINE_GEOMETRY
#define PENUMBRA_INLINE_CAPACITY 16
#include "integrators/ao.glsl"
