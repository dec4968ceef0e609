// The traversal test kernel for scenes whose primitives are inline (geometry/inline_geometry.glsl;
// the host picks it where render/inline_geometry.h's rule holds); the code is in
// tests/bvh_trace_main.glsl.
#version 450
#extension GL_GOOGLE_include_directive : require
#define PENUMBRA_INLINE_GEOMETRY
#include "tests/bvh_trace_main.glsl"
