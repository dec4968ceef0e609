// Sphere light (lecture, "Sphere Light", approaches 1-3; SCENE_FORMAT.md `sphere` with
// emission): uniform radiance leaving the surface outward, sampled on the whole sphere
// (SPHERE_AREA), on the cap visible from x (SPHERE_CAP) or uniformly in the cone it
// subtends (SPHERE_SOLID_ANGLE, PBR book 3rd ed., 14.2.2).
#ifndef PENUMBRA_LIGHTS_SPHERE_GLSL
#define PENUMBRA_LIGHTS_SPHERE_GLSL

#include "lights/light_sample.glsl"
#include "lights/light_data.glsl"
#include "sampling/warp.glsl"

// sin^2 and 1 - cos of the half-angle of the cone a sphere of radius r subtends at
// distance dist > r; 1 - cos computed as sin^2 / (1 + cos) to stay accurate for tiny or
// distant spheres (pbrt-v4, Sphere::Sample with a reference point).
void sphereCone(float r, float dist, out float cosThetaMax, out float oneMinusCos) {
    float sin2 = sqr(r / dist);
    cosThetaMax = sqrt(max(0.0, 1.0 - sin2));
    oneMinusCos = sin2 / (1.0 + cosThetaMax);
}

// Solid-angle pdf of sampling, from x, the point y (normal ny, distance d) on a sphere
// light under the chosen strategy (lecture, "Sphere Light", approaches 1-3).
float spherePdf(vec3 x, vec3 center, float r, vec3 y, vec3 ny, float d, uint sphereSampling) {
    float D = distance(x, center);
    if (D <= r) return 0.0;  // x inside the light: it emits outward, x receives nothing
    if (sphereSampling == SPHERE_SOLID_ANGLE) {
        float cosThetaMax, oneMinusCos;
        sphereCone(r, D, cosThetaMax, oneMinusCos);
        return 1.0 / (TWO_PI * oneMinusCos);
    }
    // Spelled out (preciseDot, common/math.glsl): at the visible cap's rim cosY cancels to
    // near 0, where a fused rounding moved the pdf enough for the cap chart's chi-square to
    // fail on Mesa 26 (p = 3e-6; docs/performance-history/round-17.md).
    precise vec3 w = y - x;
    precise float cosY = abs(preciseDot(w, ny) / sqrt(preciseDot(w, w)));
    if (cosY <= 0.0) return 0.0;
    float area = sphereSampling == SPHERE_AREA ? 4.0 * PI * r * r        // whole sphere
                                                      : TWO_PI * r * r * (1.0 - r / D);  // visible cap
    return areaToSolidAngle(d * d, cosY, area);
}

bool sampleSphereLight(Light light, vec3 x, vec2 u, uint sphereSampling, inout LightSample ls) {
    Primitive p = loadLightPrimitive(light.first);
    vec3 center = p.p0;
    float r = p.p1.x;
    vec3 axis = x - center;
    float D = length(axis);
    if (D <= r) return false;
    axis /= D;
    if (sphereSampling == SPHERE_SOLID_ANGLE) {
        float cosThetaMax, oneMinusCos;
        sphereCone(r, D, cosThetaMax, oneMinusCos);
        // Sampled in 1 - cos(thetaMax), the same quantity the pdf uses: from cosThetaMax,
        // 1 - cosThetaMax loses its digits to float spacing near 1 for distant spheres
        // (r/D = 1e-3: 1 - cos = 5e-7, off by ~7%), so samples would fill a cone of a
        // different size than the one 1 / (2 pi oneMinusCos) describes.
        vec3 local = squareToUniformConeOneMinusCos(u, oneMinusCos);
        ls.wi = frameToWorld(local, -axis);
        ls.pdf = 1.0 / (TWO_PI * oneMinusCos);
        // Distance to the near intersection, from the triangle (x, centre, y):
        // d = D cos(theta) - sqrt(r^2 - D^2 sin^2(theta)), clamped at the silhouette.
        // sin^2 from the sample's x and y, not 1 - cos^2: for a distant sphere cos is within
        // 5e-7 of 1 and 1 - cos^2 keeps no digits, so r^2 - D^2 sin^2 and with it the
        // distance came out up to ~1e-4 D too long, past the sphere's surface, and the
        // shadow ray (which stops at dist (1 - 1e-4)) hit the light itself.
        float cosTheta = local.z;
        float sin2 = dot(local.xy, local.xy);
        ls.dist = D * cosTheta - sqrt(max(0.0, r * r - D * D * sin2));
        ls.radiance = light.emission;
        return ls.pdf > 0.0 && ls.dist > 0.0;
    }
    vec3 ny;
    if (sphereSampling == SPHERE_AREA) {
        ny = squareToUniformSphere(u);
    } else {
        // Uniform on the cap visible from x: cos(angle from the axis) in [r/D, 1].
        ny = frameToWorld(squareToUniformCone(u, r / D), axis);
    }
    vec3 y = center + r * ny;
    vec3 toLight = y - x;
    float d2 = dot(toLight, toLight);
    if (!(d2 > 0.0)) return false;
    ls.dist = sqrt(d2);
    ls.wi = toLight / ls.dist;
    if (dot(-ls.wi, ny) <= 0.0) return false;  // back of the sphere: hidden by the sphere itself
    ls.pdf = spherePdf(x, center, r, y, ny, ls.dist, sphereSampling);
    ls.radiance = light.emission;
    return ls.pdf > 0.0 && !isinf(ls.pdf);
}

// Density (solid angle, at x) of the direction that first hits the sphere at y, normal ny,
// distance d.
float sphereLightPdf(Light light, vec3 x, vec3 y, vec3 ny, float d, uint sphereSampling) {
    Primitive p = loadLightPrimitive(light.first);
    return spherePdf(x, p.p0, p.p1.x, y, ny, d, sphereSampling);
}

// A sphere emits outward, which any hit from outside sees.
vec3 sphereEmittedRadiance(Light light) { return light.emission; }

#endif
