// What quad and mesh-triangle lights share: their front normal, where a sampled direction
// meets their plane, and the decision whether a polygon is sampled in the solid angle it
// subtends or, as the fallback, on its area (the bounds and why they are what they are).
#ifndef PENUMBRA_LIGHTS_POLYGON_FALLBACK_GLSL
#define PENUMBRA_LIGHTS_POLYGON_FALLBACK_GLSL

#include "shared/types.h"
#include "lights/light_sample.glsl"

// Front normal of a quad or triangle primitive (counter-clockwise = front).
vec3 primitiveFrontNormal(Primitive p) {
    return (p.typeAndNormals & PRIM_TYPE_MASK) == PRIM_QUAD ? normalize(cross(p.p1, p.p2))
                                                            : normalize(cross(p.p1 - p.p0, p.p2 - p.p0));
}

// ---- Solid-angle sampling of quads and triangles, and its fallback ---------------------
// A quad or triangle whose solid angle from x is below SPHERICAL_MIN_SOLID_ANGLE (sr), or that
// x sees at a grazing angle (a vertex less than asin(SPHERICAL_MIN_ELEVATION_SINE) above its
// plane), is sampled on its area instead, for that shading point and that light or triangle
// alone (pbrt-v4 falls back the same way, with its own bound on the solid angle). For tiny
// and for grazing polygons the spherical warps lose their precision in 32-bit floats: their
// angles and cosines sit within a few float spacings of the values they are subtracted from
// (the spherical polygon is small, or a thin sliver along a great circle). The grazing bound
// also keeps away from x almost in the light's plane inside its outline, where the spherical
// polygon nears a hemisphere and the warps' arcs degenerate: a polygon whose vertices are all
// at least asin(s) above its plane lies inside a disk seen within 2 pi (1 - s) = 6.09 sr.
// Both bounds were chosen by measurement (docs/guide/integrators.md, "Quad and triangle sampling";
// LightSamplingMeasure in tests/test_light_sampling.cpp): with the fallback off, chi-square
// of the spherical-rectangle map fails at 3e-4 sr and at 1 degree and passes at 1e-3 sr and
// 3 degrees; every warp fails above 6.25 sr and passes at 6.2 sr (the spherical-triangle warp
// holds down to 1e-7 sr and 0.1 degree: one pair of bounds serves both for now). With the
// fallback on, the tests pass on both sides of each bound. The decision is a function
// of the shading point and the light only, so lightPdf (MIS) takes the same one as sampleLight.
bool sphericalSolidAngleUsable(float solidAngle, LightSamplingModes modes) { return solidAngle >= modes.minSolidAngle; }

// Whether every vertex of a polygon (a triangle: v3 = v2) in the plane through v0 with unit
// normal n is seen from x at least asin(minElevationSine) above that plane: the distance of x
// from the plane over its distance to the farthest vertex.
bool sphericalElevationUsable(vec3 v0, vec3 v1, vec3 v2, vec3 v3, vec3 n, vec3 x, LightSamplingModes modes) {
    float farthest = max(max(distance(v0, x), distance(v1, x)), max(distance(v2, x), distance(v3, x)));
    return abs(dot(x - v0, n)) >= modes.minElevationSine * farthest;
}

// Where the ray x + t w (t > 0) meets the plane through v with normal n (any length).
bool planePoint(vec3 x, vec3 w, vec3 v, vec3 n, out vec3 y) {
    float t = dot(n, v - x) / dot(n, w);
    y = x + t * w;
    return t > 0.0 && !isinf(t);
}

// Completes a sample of a point y (front normal ny) on a quad or mesh light: direction,
// distance and density in solid angle. solidAnglePdf > 0: y was sampled in solid angle with
// that density; otherwise uniformly on the light's area. Points on the back of a one-sided
// light carry nothing.
bool finishPolygonSample(Light light, vec3 x, vec3 y, vec3 ny, float solidAnglePdf, inout LightSample ls) {
    vec3 toLight = y - x;
    float d2 = dot(toLight, toLight);
    if (!(d2 > 0.0)) return false;
    ls.dist = sqrt(d2);
    ls.wi = toLight / ls.dist;
    float cosY = dot(-ls.wi, ny);
    if (cosY <= 0.0 && (light.flags & LIGHT_TWO_SIDED) == 0u) return false;  // back of a one-sided light
    // p_A = 1 / area (mesh: lecture, p_A = 1 / sum A(k)), unless sampled in solid angle.
    ls.pdf = solidAnglePdf > 0.0 ? solidAnglePdf : areaToSolidAngle(d2, abs(cosY), light.area);
    ls.radiance = light.emission;
    return ls.pdf > 0.0 && !isinf(ls.pdf);
}

// Density of a direction wi that reaches a quad or mesh light at distance d under cosine
// cosY = dot(-wi, ny), when it was sampled on the light's area; 0 on the back of a one-sided
// light (sampleLight declines those points).
float polygonAreaPdf(Light light, float cosY, float d) {
    if (cosY <= 0.0 && (light.flags & LIGHT_TWO_SIDED) == 0u) return 0.0;
    cosY = abs(cosY);
    return cosY > 0.0 ? areaToSolidAngle(d * d, cosY, light.area) : 0.0;
}

// Radiance leaving a quad or mesh light with front normal nFront toward a viewer in
// direction -wi: from the front unless two-sided.
vec3 polygonEmittedRadiance(Light light, vec3 nFront, vec3 wi) {
    if ((light.flags & LIGHT_TWO_SIDED) != 0u) return light.emission;
    return dot(wi, nFront) < 0.0 ? light.emission : vec3(0.0);
}

#endif
