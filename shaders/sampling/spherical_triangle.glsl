// Uniform sampling of the solid angle a triangle subtends at a point (the spherical
// triangle), and that solid angle: the density of the warp is 1 / solidAngle in SOLID ANGLE
// measure. Arvo 1995, "Stratified Sampling of Spherical Triangles" (SIGGRAPH), in the form of
// pbrt-v4 SampleSphericalTriangle (util/sampling.cpp), with the cancellations noted below
// rewritten. Light code decides when to use it (lights/lights.glsl) and converts measures.
#ifndef PENUMBRA_SPHERICAL_TRIANGLE_GLSL
#define PENUMBRA_SPHERICAL_TRIANGLE_GLSL

#include "common/math.glsl"

// Angle between two vectors, atan2(|a x b|, a . b): no loss of digits near 0 and pi (as
// acos has), and the accurate atan2 (common/math.glsl).
float angleBetween(vec3 a, vec3 b) { return atan2Accurate(length(cross(a, b)), dot(a, b)); }

// Solid angle of the triangle (v0, v1, v2) seen from x, in [0, 2 pi], by Van Oosterom and
// Strackee 1983 ("The Solid Angle of a Plane Triangle", IEEE Trans. Biomed. Eng. 30(2)):
//   tan(Omega / 2) = |det(a, b, c)| / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|)
// with a, b, c = v_i - x. The determinant is taken as a . ((v1 - v0) x (v2 - v0)), from the
// triangle's own edges, so it keeps its relative precision for small or distant triangles,
// where Girard's alpha + beta + gamma - pi loses every digit to cancellation.
float sphericalTriangleSolidAngle(vec3 v0, vec3 v1, vec3 v2, vec3 x) {
    vec3 a = v0 - x, b = v1 - x, c = v2 - x;
    float la = length(a), lb = length(b), lc = length(c);
    float det = abs(dot(a, cross(v1 - v0, v2 - v0)));
    float den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    return 2.0 * atan2Accurate(det, den);
}

// Density w.r.t. SOLID ANGLE of a direction inside the spherical triangle: 1 / solid angle.
float sphericalTrianglePdf(float solidAngle) { return 1.0 / solidAngle; }

// A direction uniform in the spherical triangle of (v0, v1, v2) seen from x, whose solid
// angle (sphericalTriangleSolidAngle) is `solidAngle`. Arvo's two steps: u.x picks the
// sub-triangle (a, b, c') of area u.x * solidAngle, c' on the arc from a to c; u.y picks the
// point on the arc from b to c' uniformly in 1 - cos of its angle from b. Returns false for
// a degenerate triangle (x in its plane on an edge's line).
bool sampleSphericalTriangle(vec3 v0, vec3 v1, vec3 v2, vec3 x, float solidAngle, vec2 u, out vec3 w) {
    w = vec3(0.0);
    vec3 A = v0 - x, B = v1 - x, C = v2 - x;
    // Great-circle normals from each vertex's direction and the triangle's exact edge, not
    // from two nearly parallel unit vectors (whose cross product keeps few digits).
    vec3 nab = cross(A, v1 - v0), nbc = cross(B, v2 - v1), nca = cross(C, v0 - v2);
    if (dot(nab, nab) == 0.0 || dot(nbc, nbc) == 0.0 || dot(nca, nca) == 0.0) return false;
    vec3 a = normalize(A), b = normalize(B), c = normalize(C);
    nab = normalize(nab);
    nca = normalize(nca);
    // The angle alpha at a, between the arcs toward b and toward c.
    float alpha = angleBetween(nab, -nca);
    float cosAlpha = cos(alpha), sinAlpha = sin(alpha);
    // pbrt-v4 forms phi = pi + u.x Omega - alpha and then k1 = cos(phi) + cos(alpha),
    // k2 = sin(phi) - sin(alpha) cos(c), both differences of nearly equal numbers for small
    // triangles. With t = u.x Omega the same quantities without cancellation:
    //   cos(phi) + cos(alpha) = -2 sin(alpha - t/2) sin(t/2)
    //   sin(phi) - sin(alpha) = -2 cos(alpha - t/2) sin(t/2),  1 - cos(c) = |a - b|^2 / 2.
    float t = u.x * solidAngle;
    float sinHalfT = sin(0.5 * t);
    float sinPhi = sin(alpha - t), cosPhi = -cos(alpha - t);
    float oneMinusCosC = 0.5 * dot(a - b, a - b);
    float k1 = -2.0 * sin(alpha - 0.5 * t) * sinHalfT;
    float k2 = -2.0 * cos(alpha - 0.5 * t) * sinHalfT + sinAlpha * oneMinusCosC;
    // The arc b' from a to c': Arvo's cos(b') = N / D with
    //   N = k2 + (k2 cos(phi) - k1 sin(phi)) cos(alpha),  D = (k2 sin(phi) + k1 cos(phi)) sin(alpha).
    // For short arcs cos(b') rounds to 1 and sqrt(1 - cos^2) keeps no digits (samples pile up on
    // the edge a-b), so 1 - cos(b') = (D - N) / D, where, as phi + alpha = pi + t,
    //   D - N = k2 (cos(t) - 1) - k1 sin(t) = -2 k2 sin^2(t/2) - k1 sin(t).
    float D = (k2 * sinPhi + k1 * cosPhi) * sinAlpha;
    float oneMinusCosBp = clamp((-2.0 * k2 * sinHalfT * sinHalfT - k1 * sin(t)) / D, 0.0, 2.0);
    float cosBp = 1.0 - oneMinusCosBp;
    float sinBp = sqrt(max(0.0, oneMinusCosBp * (2.0 - oneMinusCosBp)));
    // Directions orthogonal to a (and to b below) from the chords c - a, c' - b, which keep
    // their digits where c is close to a, unlike c - (c.a) a.
    vec3 cPerp = (c - a) - dot(c - a, a) * a;
    if (dot(cPerp, cPerp) == 0.0) return false;
    vec3 cp = cosBp * a + sinBp * normalize(cPerp);
    // Uniform in 1 - cos(angle from b) along the arc from b to c'.
    float oneMinusCosTheta = u.y * 0.5 * dot(cp - b, cp - b);
    float cosTheta = 1.0 - oneMinusCosTheta;
    float sinTheta = sqrt(max(0.0, oneMinusCosTheta * (2.0 - oneMinusCosTheta)));
    vec3 cpPerp = (cp - b) - dot(cp - b, b) * b;
    if (dot(cpPerp, cpPerp) == 0.0) {
        w = b;  // c' = b: the arc has shrunk to a point
        return true;
    }
    w = cosTheta * b + sinTheta * normalize(cpPerp);
    return true;
}

#endif
