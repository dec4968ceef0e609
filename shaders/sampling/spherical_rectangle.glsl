// Uniform sampling of the solid angle a rectangle subtends at a point (the spherical
// rectangle): Urena, Fajardo and King 2013, "An Area-Preserving Parametrization for
// Spherical Rectangles" (EGSR, Computer Graphics Forum 32(4)), whose listing this follows.
// The density is 1 / solidAngle in SOLID ANGLE measure. Light code decides when to use it
// (lights/lights.glsl) and converts measures.
#ifndef PENUMBRA_SPHERICAL_RECTANGLE_GLSL
#define PENUMBRA_SPHERICAL_RECTANGLE_GLSL

#include "common/math.glsl"

// The rectangle corner + s ex + t ey (ex orthogonal to ey) in the local frame of the
// paper: x0 <= x <= x1, y0 <= y <= y1 in the plane z = z0 < 0, with the origin at the
// shading point.
struct SphericalRectangle {
    vec3 ex, ey, ez;     // unit axes (world); ez points away from the rectangle
    float x0, x1, y0, y1, z0;
    float b0, b1, k;     // the paper's constants of the inverse CDF in x
    float solidAngle;
};

// Set-up. `solidAngle` is the rectangle's solid angle from x, computed by the caller
// (lights.glsl, from two spherical triangles: the paper's S = sum of the four interior
// angles - 2 pi cancels to nothing for small rectangles). The interior angles g_i are
// taken as atan2(|n_i x n_j|, n_i . n_j) of the unnormalized edge-plane normals, whose
// cross products and dot products reduce exactly to the forms below; the paper's
// acos(-n_i . n_j) loses half its digits where g_i nears 0 or pi (x near the plane).
SphericalRectangle makeSphericalRectangle(vec3 corner, vec3 edgeU, vec3 edgeV, vec3 x, float solidAngle) {
    SphericalRectangle r;
    float lu = length(edgeU), lv = length(edgeV);
    r.ex = edgeU / lu;
    r.ey = edgeV / lv;
    r.ez = cross(r.ex, r.ey);
    vec3 d = corner - x;
    r.z0 = dot(d, r.ez);
    if (r.z0 > 0.0) {
        r.ez = -r.ez;
        r.z0 = -r.z0;
    }
    r.x0 = dot(d, r.ex);
    r.y0 = dot(d, r.ey);
    r.x1 = r.x0 + lu;
    r.y1 = r.y0 + lv;
    float z0 = r.z0, az = abs(z0), z2 = z0 * z0;
    // Edge-plane normals n0 ~ (0, z0, -y0), n1 ~ (-z0, 0, x1), n2 ~ (0, -z0, y1), n3 ~ (z0, 0, -x0).
    r.b0 = -r.y0 / sqrt(z2 + r.y0 * r.y0);  // n0.z
    r.b1 = r.y1 / sqrt(z2 + r.y1 * r.y1);   // n2.z
    float g2 = atan2Accurate(az * sqrt(r.x0 * r.x0 + r.y1 * r.y1 + z2), r.x0 * r.y1);
    float g3 = atan2Accurate(az * sqrt(r.x0 * r.x0 + r.y0 * r.y0 + z2), -r.x0 * r.y0);
    r.k = TWO_PI - g2 - g3;
    r.solidAngle = solidAngle;
    return r;
}

// Density w.r.t. SOLID ANGLE inside the spherical rectangle: 1 / solid angle.
float sphericalRectanglePdf(float solidAngle) { return 1.0 / solidAngle; }

// The point on the rectangle, relative to x (in world axes), whose direction is uniform in
// the spherical rectangle: u.x by the inverse CDF of the x coordinate (the area of the
// sub-rectangle left of it is u.x S), u.y uniform in the height h = y / sqrt(x^2 + y^2 + z^2)
// along that vertical line (the paper, sections 3-4).
vec3 sampleSphericalRectangle(SphericalRectangle r, vec2 u) {
    float au = u.x * r.solidAngle + r.k;
    float fu = (cos(au) * r.b0 - r.b1) / sin(au);
    float cu = clamp((fu > 0.0 ? 1.0 : -1.0) / sqrt(fu * fu + r.b0 * r.b0), -1.0, 1.0);
    float xu = -(cu * r.z0) / max(sqrt(max(0.0, 1.0 - cu * cu)), 1e-30);
    xu = clamp(xu, r.x0, r.x1);
    float dd = sqrt(xu * xu + r.z0 * r.z0);
    float h0 = r.y0 / sqrt(dd * dd + r.y0 * r.y0);
    float h1 = r.y1 / sqrt(dd * dd + r.y1 * r.y1);
    float hv = h0 + u.y * (h1 - h0), hv2 = hv * hv;
    float yv = hv2 < 1.0 - 1e-6 ? (hv * dd) / sqrt(1.0 - hv2) : r.y1;
    yv = clamp(yv, r.y0, r.y1);
    return xu * r.ex + yv * r.ey + r.z0 * r.ez;
}

#endif
