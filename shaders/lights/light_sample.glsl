// What every light kind's sampler returns (LightSample), the integrator options that choose
// how area lights are sampled (LightSamplingModes), and the one conversion of an area-measure
// density into solid angle at the shading point. The per-kind files (point.glsl ...
// mesh.glsl) build on these; lights.glsl dispatches to them.
#ifndef PENUMBRA_LIGHT_SAMPLE_GLSL
#define PENUMBRA_LIGHT_SAMPLE_GLSL

#include "shared/types.h"
#include "common/math.glsl"

struct LightSample {
    vec3 wi;         // unit direction from x toward the light
    float dist;      // distance to the sampled point; FLOAT_MAX at infinity
    vec3 radiance;   // Le along -wi (area, environment); I/d^2 (point); E (directional)
    float pdf;       // solid-angle density of wi for this light; 1 for delta lights
    bool isDelta;
    // Quad lights: 1 / the quad's solid angle from x where the quad is sampled in solid
    // angle from x, 0 where it is sampled on its area; 0 for other kinds. It depends on x and
    // the light alone, so the density of any other direction toward the same quad from the
    // same x is this value too (KnownQuadDensity).
    float quadSolidAnglePdf;
};

// A quad light's density at x known from a light sample taken at the same x
// (LightSample.quadSolidAnglePdf), which lightPdf then uses instead of computing the
// quad's solid angle again. `known` must be a constant at the call site: where it is true
// the computation is compiled out, which is the point, since llvmpipe (Mesa 22.3) runs both
// sides of every branch (docs/performance-history/round-06.md).
struct KnownQuadDensity {
    bool known;
    float solidAnglePdf;  // as LightSample.quadSolidAnglePdf
};

KnownQuadDensity unknownQuadDensity() { return KnownQuadDensity(false, 0.0); }

// The integrator options that choose how each kind of area light is sampled (SPHERE_*,
// QUAD_*, TRIANGLE_*); sampleLight and lightPdf must be given the same.
struct LightSamplingModes {
    uint sphere;
    uint quad;
    uint triangle;
    // The fallback bounds (polygon_fallback.glsl): SPHERICAL_MIN_SOLID_ANGLE and
    // SPHERICAL_MIN_ELEVATION_SINE in the integrator; the light-sampling test kernel can
    // lower them to measure the warps.
    float minSolidAngle;
    float minElevationSine;
};

// A sample that carries nothing yet: its fields are what sampleLight returns on refusal.
LightSample emptyLightSample(vec3 n) {
    LightSample ls;
    ls.isDelta = false;
    ls.pdf = 0.0;
    ls.quadSolidAnglePdf = 0.0;
    ls.radiance = vec3(0.0);
    ls.dist = FLOAT_MAX;
    ls.wi = n;
    return ls;
}

// The solid-angle density at x of a point y drawn uniformly on `area`, seen at distance^2 d2
// under cosine cosY from y's normal (lecture, "Sphere Light": Caution!):
//   p_w(wi) = p_A(y) * d^2 / |cos theta_y|,  p_A = 1 / area.
// Every area-measure density in lights/ is turned into solid angle here and nowhere else.
float areaToSolidAngle(float d2, float cosY, float area) { return d2 / (cosY * area); }

#endif
