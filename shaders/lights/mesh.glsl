// Mesh light (lecture, "Mesh Lights"; SCENE_FORMAT.md `mesh` with emission): a triangle chosen
// in proportion to its area (the mesh's alias table), then a point uniform on its area
// (TRIANGLE_AREA) or a direction uniform in its solid angle (TRIANGLE_SOLID_ANGLE: Arvo 1995
// in pbrt-v4's SampleSphericalTriangle form).
#ifndef PENUMBRA_LIGHTS_MESH_GLSL
#define PENUMBRA_LIGHTS_MESH_GLSL

#include "lights/light_sample.glsl"
#include "lights/light_data.glsl"
#include "lights/alias.glsl"
#include "lights/polygon_fallback.glsl"
#include "sampling/warp.glsl"
#include "sampling/spherical_triangle.glsl"

// Area of a triangle primitive.
float triangleArea(Primitive p) { return 0.5 * length(cross(p.p1 - p.p0, p.p2 - p.p0)); }

// Whether mesh triangle p is sampled in solid angle from x, with its solid angle.
bool triangleSolidAngle(Primitive p, vec3 x, LightSamplingModes modes, out float omega) {
    omega = sphericalTriangleSolidAngle(p.p0, p.p1, p.p2, x);
    return sphericalSolidAngleUsable(omega, modes) &&
           sphericalElevationUsable(p.p0, p.p1, p.p2, p.p2, primitiveFrontNormal(p), x, modes);
}

// A point on triangle p whose direction from x is uniform in its solid angle `omega`.
bool sampleTriangleSolidAngle(Primitive p, vec3 x, vec2 u, float omega, out vec3 y) {
    y = x;
    vec3 w;
    if (!sampleSphericalTriangle(p.p0, p.p1, p.p2, x, omega, u, w)) return false;
    return planePoint(x, w, p.p0, cross(p.p1 - p.p0, p.p2 - p.p0), y);
}

// The emission texture's factor at point y of mesh triangle `primitive` (p), through its
// interpolated uvs (textures/textures.glsl, emissionTexture). Only kernels that include the
// texture lookups before the lights (the render kernels) read it; others see uniform emitters.
#ifdef PENUMBRA_TEXTURES_GLSL
vec3 meshEmissionTexture(uint primitive, Primitive p, vec3 y) {
    if (!hasEmissionTextures()) return vec3(1.0);
    // Barycentrics of y (on p's plane) by Cramer's rule on the edge Gram matrix (Ericson,
    // "Real-Time Collision Detection", section 3.4); a sampled triangle has non-zero area.
    vec3 e1 = p.p1 - p.p0, e2 = p.p2 - p.p0, d = y - p.p0;
    float d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2), d20 = dot(d, e1), d21 = dot(d, e2);
    float denom = d00 * d11 - d01 * d01;
    float b1 = (d11 * d20 - d01 * d21) / denom, b2 = (d00 * d21 - d01 * d20) / denom;
    TriangleUvs t = uvs[primitive];
    return emissionTexture(p.material, (1.0 - b1 - b2) * t.uv01.xy + b1 * t.uv01.zw + b2 * t.uv2.xy);
}
#else
vec3 meshEmissionTexture(uint primitive, Primitive p, vec3 y) { return vec3(1.0); }
#endif

// A mesh light reduced to one of its triangles, p (light selection "bvh" chooses triangles,
// not meshes): the same light with the triangle's area, so that sampleMeshTriangle and
// meshLightPdf give that triangle's own densities (its pmf A_k / A becomes 1).
Light meshTriangleLight(Light light, Primitive p) {
    light.area = triangleArea(p);
    return light;
}

// A point on triangle `primitive` (p) of the mesh from u; the density is the mesh's: the
// triangle's pmf triangleArea(p) / light.area times the point's density on the triangle. The
// density does not depend on the emission texture (it is positive wherever emission can be):
// a textured emitter carries the texture in the sample's radiance instead, which keeps every
// pdf, and MIS with BRDF-sampled hits, as for a uniform emitter.
bool sampleMeshTriangle(Light light, uint primitive, Primitive p, vec3 x, vec2 u, LightSamplingModes modes,
                        inout LightSample ls) {
    vec3 ny = primitiveFrontNormal(p);
    vec3 y;
    float solidAnglePdf = 0.0;  // > 0: y sampled in solid angle with this density
    float omega;
    if (modes.triangle == TRIANGLE_SOLID_ANGLE && triangleSolidAngle(p, x, modes, omega)) {
        if (!sampleTriangleSolidAngle(p, x, u, omega, y)) return false;
        // pmf of the triangle (area / total, the alias table's) times uniform in its solid angle.
        solidAnglePdf = triangleArea(p) / (light.area * omega);
    } else {
        vec3 b = squareToUniformTriangle(u);
        y = b.x * p.p0 + b.y * p.p1 + b.z * p.p2;
    }
    if (!finishPolygonSample(light, x, y, ny, solidAnglePdf, ls)) return false;
    ls.radiance *= meshEmissionTexture(primitive, p, y);
    return true;
}

// u.z picks the triangle (probability area / total), u.xy the point on it.
bool sampleMeshLight(Light light, vec3 x, vec3 u, LightSamplingModes modes, inout LightSample ls) {
    AliasEntry e = sampleAlias(light.first, light.count, u.z, true);
    return sampleMeshTriangle(light, e.item, loadLightPrimitive(e.item), x, u.xy, modes, ls);
}

// Density (solid angle, at x) of a direction wi that first hits triangle `primitive` of the
// mesh at distance d, its front normal ny; the same decision as sampleMeshLight.
float meshLightPdf(Light light, vec3 x, vec3 wi, vec3 ny, float d, uint primitive, LightSamplingModes modes) {
    float cosY = dot(-wi, ny);
    if (cosY <= 0.0 && (light.flags & LIGHT_TWO_SIDED) == 0u) return 0.0;
    if (modes.triangle == TRIANGLE_SOLID_ANGLE) {
        // The hit triangle k: pmf_k / Omega_k, pmf_k = A_k / A the alias table's probability.
        Primitive p = loadLightPrimitive(primitive);
        float omega;
        if (triangleSolidAngle(p, x, modes, omega)) return triangleArea(p) / (light.area * omega);
    }
    return polygonAreaPdf(light, cosY, d);
}

#endif
