// What evaluating a BRDF at a pair of directions returns: its value and the density with
// which its sampling produces the incident direction, together. Both estimates of a
// direct-lighting sample need both, and a lobe's costly part serves both (Phong's cos^n, an
// exp and a log; GGX's D), so one evaluation gives both instead of leaving the compiler to
// merge two (it merged most: docs/performance-history/round-06.md).
#ifndef PENUMBRA_BSDF_VALUE_GLSL
#define PENUMBRA_BSDF_VALUE_GLSL

struct BsdfValue {
    vec3 f;     // f(wo, wi)
    float pdf;  // solid-angle density of wi under bsdfSample
};

#endif
