// Quad light (SCENE_FORMAT.md `quad` with emission): uniform radiance from its front face
// (or both), sampled uniformly on its area (QUAD_AREA) or uniformly in the solid angle it
// subtends (QUAD_SOLID_ANGLE): a rectangle as a spherical rectangle (Urena, Fajardo and King
// 2013), any other parallelogram as two spherical triangles (Arvo 1995).
#ifndef PENUMBRA_LIGHTS_QUAD_GLSL
#define PENUMBRA_LIGHTS_QUAD_GLSL

#include "lights/light_sample.glsl"
#include "lights/light_data.glsl"
#include "lights/polygon_fallback.glsl"
#include "sampling/spherical_rectangle.glsl"
#include "sampling/spherical_triangle.glsl"

// A quad whose edges are orthogonal (LIGHT_RECTANGLE, decided on the host) is sampled as a
// spherical rectangle, any other as two spherical triangles (origin, origin + u, origin +
// u + v) and (origin, origin + u + v, origin + v). In scenes without such other quads the
// answer is true at compile time, and the triangles' code is compiled out.
bool quadIsRectangle(Light light) { return !hasParallelogramLights() || (light.flags & LIGHT_RECTANGLE) != 0u; }

// The solid angles of the quad's two triangles from x; whether the quad is sampled in solid
// angle from x (else on its area): seen above the grazing bound, and the rectangle's total
// solid angle, or each triangle's, above the smallest.
bool quadSolidAngles(Light light, Primitive p, vec3 x, LightSamplingModes modes, out float omega0, out float omega1) {
    vec3 v0 = p.p0, v1 = p.p0 + p.p1, v2 = v1 + p.p2, v3 = p.p0 + p.p2;
    omega0 = sphericalTriangleSolidAngle(v0, v1, v2, x);
    omega1 = sphericalTriangleSolidAngle(v0, v2, v3, x);
    if (!sphericalElevationUsable(v0, v1, v2, v3, primitiveFrontNormal(p), x, modes)) return false;
    if (quadIsRectangle(light)) return sphericalSolidAngleUsable(omega0 + omega1, modes);
    return sphericalSolidAngleUsable(omega0, modes) && sphericalSolidAngleUsable(omega1, modes);
}

// A point on quad p whose direction from x is uniform in the quad's solid angle
// omega0 + omega1 (quadSolidAngles): the spherical rectangle, or one of the two spherical
// triangles chosen in proportion to its solid angle (with uChoice) and sampled uniformly.
bool sampleQuadSolidAngle(Light light, Primitive p, vec3 x, vec2 u, float uChoice, float omega0, float omega1,
                          out vec3 y) {
    y = x;
    if (quadIsRectangle(light)) {
        SphericalRectangle r = makeSphericalRectangle(p.p0, p.p1, p.p2, x, omega0 + omega1);
        y = x + sampleSphericalRectangle(r, u);
        return true;
    }
    vec3 v0 = p.p0, v1 = p.p0 + p.p1, v2 = v1 + p.p2, v3 = p.p0 + p.p2;
    bool first = uChoice * (omega0 + omega1) < omega0;
    vec3 a = v0, b = first ? v1 : v2, c = first ? v2 : v3;
    vec3 w;
    if (!sampleSphericalTriangle(a, b, c, x, first ? omega0 : omega1, u, w)) return false;
    return planePoint(x, w, p.p0, cross(p.p1, p.p2), y);
}

bool sampleQuadLight(Light light, vec3 x, vec3 u, LightSamplingModes modes, inout LightSample ls) {
    Primitive p = loadLightPrimitive(light.first);
    vec3 ny = primitiveFrontNormal(p);
    vec3 y;
    float solidAnglePdf = 0.0;  // > 0: y sampled in solid angle with this density
    float omega0, omega1;
    if (modes.quad == QUAD_SOLID_ANGLE && quadSolidAngles(light, p, x, modes, omega0, omega1)) {
        solidAnglePdf = 1.0 / (omega0 + omega1);
        ls.quadSolidAnglePdf = solidAnglePdf;
        if (!sampleQuadSolidAngle(light, p, x, u.xy, u.z, omega0, omega1, y)) return false;
    } else {
        y = p.p0 + u.x * p.p1 + u.y * p.p2;
    }
    return finishPolygonSample(light, x, y, ny, solidAnglePdf, ls);
}

// Density (solid angle, at x) of a direction wi that first hits the quad at distance d,
// its front normal ny; the same area / solid-angle decision as sampleQuadLight, or the one
// a light sample from x took (`known`).
float quadLightPdf(Light light, vec3 x, vec3 wi, vec3 ny, float d, LightSamplingModes modes, KnownQuadDensity known) {
    float cosY = dot(-wi, ny);
    if (cosY <= 0.0 && (light.flags & LIGHT_TWO_SIDED) == 0u) return 0.0;
    if (modes.quad == QUAD_SOLID_ANGLE) {
        if (known.known) {
            if (known.solidAnglePdf > 0.0) return known.solidAnglePdf;
        } else {
            float omega0, omega1;
            if (quadSolidAngles(light, loadLightPrimitive(light.first), x, modes, omega0, omega1))
                return 1.0 / (omega0 + omega1);
        }
    }
    return polygonAreaPdf(light, cosY, d);
}

#endif
