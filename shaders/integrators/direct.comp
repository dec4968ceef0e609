// The direct-illumination kernel over the BVH; the code is in integrators/direct.glsl. Its twin
// direct_inline<N>.comp is the same kernel for scenes whose primitives are compiled in
// (geometry/inline_geometry.glsl). Two modules, so that a kernel that traverses carries
// none of the unrolled inline tests, whose front end llvmpipe runs again on every start
// (docs/PERFORMANCE.md, "Round 8").
#version 450
#extension GL_GOOGLE_include_directive : require
#include "integrators/direct.glsl"
