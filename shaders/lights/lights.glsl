// Lights (lecture, "Light Sources"; SCENE_FORMAT.md): choosing a light, sampling a direction
// toward it, the density of that direction, and emitted radiance. Every pdf returned here is
// in SOLID ANGLE at the shading point x, for the given light alone (selection probability
// not included): area-measure densities are converted here and nowhere else, with
//   p_w(wi) = p_A(y) * d^2 / |cos theta_y|      (lecture, "Sphere Light": Caution!)
// Delta lights (point, directional) have no density: their samples carry isDelta.
// Quads and mesh triangles are sampled on their area or in the solid angle they subtend
// (QUAD_*, TRIANGLE_*); the solid-angle warps give densities in solid angle already.
#ifndef PENUMBRA_LIGHTS_GLSL
#define PENUMBRA_LIGHTS_GLSL

#include "shared/types.h"
#include "common/specialization.glsl"
#include "common/math.glsl"
#include "sampling/warp.glsl"
#include "sampling/spherical_rectangle.glsl"
#include "sampling/spherical_triangle.glsl"
#include "geometry/bvh.glsl"
#include "lights/light_data.glsl"


// Walker's alias method over lightTable/meshTable entries [offset, offset + count) with one
// uniform number: its integer part picks the slot, its fraction flips the slot's coin.
AliasEntry aliasEntry(uint index, bool mesh) {
    // Two separate reads rather than a select of whole structs: the two buffer blocks have
    // distinct struct types in SPIR-V, which such a select violates.
    if (mesh) return loadMeshAlias(index);
    return loadLightAlias(index);
}

AliasEntry sampleAlias(uint offset, uint count, float u, bool mesh) {
    float scaled = u * float(count);
    uint slot = min(uint(scaled), count - 1u);
    float coin = scaled - float(slot);
    AliasEntry e = aliasEntry(offset + slot, mesh);
    if (coin >= e.probability) e = aliasEntry(offset + e.alias, mesh);
    return e;
}

// Picks a light from the selection (sub-)table at [offset, offset + count); pmf is its
// probability within that table.
uint selectLight(uint offset, uint count, float u, out float pmf) {
    AliasEntry e = sampleAlias(offset, count, u, false);
    pmf = e.pmf;
    return e.item;
}

struct LightSample {
    vec3 wi;         // unit direction from x toward the light
    float dist;      // distance to the sampled point; FLOAT_MAX at infinity
    vec3 radiance;   // Le along -wi (area, environment); I/d^2 (point); E (directional)
    float pdf;       // solid-angle density of wi for this light; 1 for delta lights
    bool isDelta;
};

// Front normal of a quad or triangle primitive (counter-clockwise = front).
vec3 primitiveFrontNormal(Primitive p) {
    return (p.typeAndNormals & PRIM_TYPE_MASK) == PRIM_QUAD ? normalize(cross(p.p1, p.p2))
                                                            : normalize(cross(p.p1 - p.p0, p.p2 - p.p0));
}

// Radiance leaving an emitter with front normal nFront toward a viewer in direction -wi
// (wi points from the viewer to the emitter). Spheres emit outward, which any hit from
// outside sees; quads and meshes from their front unless two-sided.
vec3 emittedRadiance(Light light, vec3 nFront, vec3 wi) {
    if (lightIs(light, LIGHT_SPHERE) || (light.flags & LIGHT_TWO_SIDED) != 0u) return light.emission;
    return dot(wi, nFront) < 0.0 ? light.emission : vec3(0.0);
}

// The integrator options that choose how each kind of area light is sampled (SPHERE_*,
// QUAD_*, TRIANGLE_*); sampleLight and lightPdf must be given the same.
struct LightSamplingModes {
    uint sphere;
    uint quad;
    uint triangle;
    // The fallback bounds (below): SPHERICAL_MIN_SOLID_ANGLE and SPHERICAL_MIN_ELEVATION_SINE
    // in the integrator; the light-sampling test kernel can lower them to measure the warps.
    float minSolidAngle;
    float minElevationSine;
};

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
// Both bounds were chosen by measurement (README, "Quad and triangle sampling";
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

// Whether mesh triangle p is sampled in solid angle from x, with its solid angle.
bool triangleSolidAngle(Primitive p, vec3 x, LightSamplingModes modes, out float omega) {
    omega = sphericalTriangleSolidAngle(p.p0, p.p1, p.p2, x);
    return sphericalSolidAngleUsable(omega, modes) &&
           sphericalElevationUsable(p.p0, p.p1, p.p2, p.p2, primitiveFrontNormal(p), x, modes);
}

// A quad whose edges are orthogonal (to 1e-5 of their lengths' product: scene files write
// rectangles in decimals) is sampled as a spherical rectangle, any other as two spherical
// triangles (origin, origin + u, origin + u + v) and (origin, origin + u + v, origin + v).
bool quadIsRectangle(Primitive p) { return abs(dot(p.p1, p.p2)) <= 1e-5 * length(p.p1) * length(p.p2); }

// The solid angles of the quad's two triangles from x; whether the quad is sampled in solid
// angle from x (else on its area): seen above the grazing bound, and the rectangle's total
// solid angle, or each triangle's, above the smallest.
bool quadSolidAngles(Primitive p, vec3 x, LightSamplingModes modes, out float omega0, out float omega1) {
    vec3 v0 = p.p0, v1 = p.p0 + p.p1, v2 = v1 + p.p2, v3 = p.p0 + p.p2;
    omega0 = sphericalTriangleSolidAngle(v0, v1, v2, x);
    omega1 = sphericalTriangleSolidAngle(v0, v2, v3, x);
    if (!sphericalElevationUsable(v0, v1, v2, v3, primitiveFrontNormal(p), x, modes)) return false;
    if (quadIsRectangle(p)) return sphericalSolidAngleUsable(omega0 + omega1, modes);
    return sphericalSolidAngleUsable(omega0, modes) && sphericalSolidAngleUsable(omega1, modes);
}

// Where the ray x + t w (t > 0) meets the plane through v with normal n (any length).
bool planePoint(vec3 x, vec3 w, vec3 v, vec3 n, out vec3 y) {
    float t = dot(n, v - x) / dot(n, w);
    y = x + t * w;
    return t > 0.0 && !isinf(t);
}

// A point on quad p whose direction from x is uniform in the quad's solid angle
// omega0 + omega1 (quadSolidAngles): the spherical rectangle, or one of the two spherical
// triangles chosen in proportion to its solid angle (with uChoice) and sampled uniformly.
bool sampleQuadSolidAngle(Primitive p, vec3 x, vec2 u, float uChoice, float omega0, float omega1, out vec3 y) {
    y = x;
    if (quadIsRectangle(p)) {
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

// Area of a triangle primitive.
float triangleArea(Primitive p) { return 0.5 * length(cross(p.p1 - p.p0, p.p2 - p.p0)); }

// A point on triangle p whose direction from x is uniform in its solid angle `omega`.
bool sampleTriangleSolidAngle(Primitive p, vec3 x, vec2 u, float omega, out vec3 y) {
    y = x;
    vec3 w;
    if (!sampleSphericalTriangle(p.p0, p.p1, p.p2, x, omega, u, w)) return false;
    return planePoint(x, w, p.p0, cross(p.p1 - p.p0, p.p2 - p.p0), y);
}

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
    float cosY = abs(dot(normalize(y - x), ny));
    if (cosY <= 0.0) return 0.0;
    float area = sphereSampling == SPHERE_AREA ? 4.0 * PI * r * r        // whole sphere
                                                      : TWO_PI * r * r * (1.0 - r / D);  // visible cap
    return d * d / (cosY * area);
}

// Samples a direction toward light `index` from x (shading normal n, used by the
// environment's cosine sampling). u: three uniform numbers; modes: how area lights are
// sampled. Returns false when the sample carries nothing (back side of a one-sided light,
// x inside a sphere light, ...).
bool sampleLight(uint index, vec3 x, vec3 n, vec3 u, LightSamplingModes modes, out LightSample ls) {
    uint sphereSampling = modes.sphere;
    Light light = loadLight(index);
    ls.isDelta = false;
    ls.pdf = 0.0;
    ls.radiance = vec3(0.0);
    ls.dist = FLOAT_MAX;
    ls.wi = n;
    if (lightIs(light, LIGHT_POINT)) {
        vec3 toLight = light.position - x;
        float d2 = dot(toLight, toLight);
        if (!(d2 > 0.0)) return false;
        ls.dist = sqrt(d2);
        ls.wi = toLight / ls.dist;
        ls.radiance = light.emission / d2;  // I / d^2 (lecture, "Point Light")
        ls.pdf = 1.0;
        ls.isDelta = true;
        return true;
    }
    if (lightIs(light, LIGHT_DIRECTIONAL)) {
        ls.wi = -light.position;  // position holds the unit direction of travel
        ls.radiance = light.emission;
        ls.pdf = 1.0;
        ls.isDelta = true;
        return true;
    }
    if (lightIs(light, LIGHT_ENVIRONMENT)) {
        // Cosine-weighted about n: proportional to the integrand's cosine for a constant sky.
        vec3 local = squareToCosineHemisphere(u.xy);
        ls.wi = frameToWorld(local, n);
        ls.pdf = cosineHemispherePdf(local.z);
        ls.radiance = light.emission;
        return ls.pdf > 0.0;
    }

    vec3 y, ny;
    // > 0 when y was sampled in solid angle: the density of its direction (selection of the
    // mesh triangle included), which then replaces the area-to-solid-angle conversion below.
    float solidAnglePdf = 0.0;
    if (lightIs(light, LIGHT_SPHERE)) {
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
            vec3 local = squareToUniformConeOneMinusCos(u.xy, oneMinusCos);
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
        if (sphereSampling == SPHERE_AREA) {
            ny = squareToUniformSphere(u.xy);
        } else {
            // Uniform on the cap visible from x: cos(angle from the axis) in [r/D, 1].
            ny = frameToWorld(squareToUniformCone(u.xy, r / D), axis);
        }
        y = center + r * ny;
    } else if (lightIs(light, LIGHT_QUAD)) {
        Primitive p = loadLightPrimitive(light.first);
        ny = primitiveFrontNormal(p);
        float omega0, omega1;
        if (modes.quad == QUAD_SOLID_ANGLE && quadSolidAngles(p, x, modes, omega0, omega1)) {
            if (!sampleQuadSolidAngle(p, x, u.xy, u.z, omega0, omega1, y)) return false;
            solidAnglePdf = 1.0 / (omega0 + omega1);
        } else {
            y = p.p0 + u.x * p.p1 + u.y * p.p2;
        }
    } else if (lightIs(light, LIGHT_MESH)) {  // a triangle with probability area / total, then a point on it
        AliasEntry e = sampleAlias(light.first, light.count, u.z, true);
        Primitive p = loadLightPrimitive(e.item);
        ny = primitiveFrontNormal(p);
        float omega;
        if (modes.triangle == TRIANGLE_SOLID_ANGLE && triangleSolidAngle(p, x, modes, omega)) {
            if (!sampleTriangleSolidAngle(p, x, u.xy, omega, y)) return false;
            // pmf of the triangle (area / total, the alias table's) times uniform in its solid angle.
            solidAnglePdf = triangleArea(p) / (light.area * omega);
        } else {
            vec3 b = squareToUniformTriangle(u.xy);
            y = b.x * p.p0 + b.y * p.p1 + b.z * p.p2;
        }
    } else {
        return false;
    }

    vec3 toLight = y - x;
    float d2 = dot(toLight, toLight);
    if (!(d2 > 0.0)) return false;
    ls.dist = sqrt(d2);
    ls.wi = toLight / ls.dist;
    float cosY = dot(-ls.wi, ny);
    if (lightIs(light, LIGHT_SPHERE)) {
        if (cosY <= 0.0) return false;  // back of the sphere: hidden by the sphere itself
        ls.pdf = spherePdf(x, loadLightPrimitive(light.first).p0, loadLightPrimitive(light.first).p1.x, y, ny, ls.dist, sphereSampling);
    } else {
        if (cosY <= 0.0 && (light.flags & LIGHT_TWO_SIDED) == 0u) return false;  // back of a one-sided light
        // p_A = 1 / area (mesh: lecture, p_A = 1 / sum A(k)), unless sampled in solid angle.
        ls.pdf = solidAnglePdf > 0.0 ? solidAnglePdf : d2 / (abs(cosY) * light.area);
    }
    ls.radiance = light.emission;
    return ls.pdf > 0.0 && !isinf(ls.pdf);
}

// Density (solid angle, at x) with which sampleLight(index, x, n, ., modes) produces wi,
// given that the ray x + t wi first hits this light at y (geometric normal ny) at distance d,
// on primitive `primitive`; for the environment, y, ny, d and primitive are ignored.
float lightPdf(uint index, vec3 x, vec3 n, vec3 wi, vec3 y, vec3 ny, float d, uint primitive, LightSamplingModes modes) {
    uint sphereSampling = modes.sphere;
    Light light = loadLight(index);
    if (lightIs(light, LIGHT_ENVIRONMENT)) return max(dot(wi, n), 0.0) * INV_PI;
    if (lightIs(light, LIGHT_POINT) || lightIs(light, LIGHT_DIRECTIONAL)) return 0.0;
    if (lightIs(light, LIGHT_SPHERE)) {
        Primitive p = loadLightPrimitive(light.first);
        return spherePdf(x, p.p0, p.p1.x, y, ny, d, sphereSampling);
    }
    // Quad and mesh: sampleLight declines points on the back of a one-sided light, so the
    // density of a direction that reaches its back is 0.
    float cosY = dot(-wi, ny);
    if (cosY <= 0.0 && (light.flags & LIGHT_TWO_SIDED) == 0u) return 0.0;
    // Sampled in solid angle from x (the same decision as sampleLight's): uniform there.
    if (lightIs(light, LIGHT_QUAD) && modes.quad == QUAD_SOLID_ANGLE) {
        float omega0, omega1;
        if (quadSolidAngles(loadLightPrimitive(light.first), x, modes, omega0, omega1)) return 1.0 / (omega0 + omega1);
    }
    if (lightIs(light, LIGHT_MESH) && modes.triangle == TRIANGLE_SOLID_ANGLE) {
        // The hit triangle k: pmf_k / Omega_k, pmf_k = A_k / A the alias table's probability.
        Primitive p = loadLightPrimitive(primitive);
        float omega;
        if (triangleSolidAngle(p, x, modes, omega)) return triangleArea(p) / (light.area * omega);
    }
    // Area sampling: p_A = 1 / area, in solid angle.
    cosY = abs(cosY);
    return cosY > 0.0 ? d * d / (cosY * light.area) : 0.0;
}

#endif
