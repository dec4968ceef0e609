// Constants and small vector helpers used by every kernel: orthonormal frames and
// safe arithmetic. No scene access here.
#ifndef PENUMBRA_MATH_GLSL
#define PENUMBRA_MATH_GLSL

const float PI = 3.14159265358979323846;
const float TWO_PI = 6.28318530717958647692;
const float INV_PI = 0.31830988618379067154;
const float INV_TWO_PI = 0.15915494309189533577;
const float INV_FOUR_PI = 0.07957747154594766788;
const float FLOAT_MAX = 3.402823466e38;

// Orthonormal basis around unit n (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited", JCGT 6(1)): t, b, n right-handed, continuous except at n.z = -1.
void buildFrame(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// Local (t, b, n) coordinates -> world.
vec3 frameToWorld(vec3 local, vec3 n) {
    vec3 t, b;
    buildFrame(n, t, b);
    return local.x * t + local.y * b + local.z * n;
}

vec3 frameToLocal(vec3 world, vec3 n) {
    vec3 t, b;
    buildFrame(n, t, b);
    return vec3(dot(world, t), dot(world, b), dot(world, n));
}

float maxComponent(vec3 v) { return max(v.x, max(v.y, v.z)); }
float meanComponent(vec3 v) { return (v.x + v.y + v.z) / 3.0; }

bool isFiniteVec(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

float sqr(float x) { return x * x; }

// dot(a, b) and cross(a, b) with no fused multiply-add in them, for code whose rounding must
// not depend on the driver. `precise` (SPIR-V NoContraction) keeps separate instructions from
// being fused, but dot and cross are one instruction each (OpDot, GLSL.std.450 Cross), which a
// driver may compute with fmas inside: Mesa 26's lavapipe does (docs/performance-history/round-17.md). Spelled out,
// every product and sum is its own instruction, in glm's order (glm::dot:
// x + y, then + z; glm::cross), which the CPU mirrors in host/bvh compute with -ffp-contract=off.
float preciseDot(vec3 a, vec3 b) {
    precise float d = a.x * b.x + a.y * b.y + a.z * b.z;
    return d;
}
vec3 preciseCross(vec3 a, vec3 b) {
    precise vec3 c = vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
    return c;
}

// atan(y, x) to about float precision (a few ULP). Vulkan lets atan be off by 4096 ULP and
// lavapipe's is off by ~2e-5 relative (measured through the solid angles of
// sampling/spherical_*.glsl, whose pdfs integrated to 1 + 2e-5), so the built-in is not
// used: this is Cephes' atanf (S. Moshier, Cephes Math Library, atanf.c: peak relative error
// 1.9e-7) on min(|x|, |y|) / max(|x|, |y|) in [0, 1], reduced once more by pi/4 above
// tan(pi/8), then moved into the quadrant of (x, y). Only selects and one division, where
// the built-in with a Newton step needed a sin and a cos more; every sample of a quad light
// in solid angle takes several of these, and the change made the Cornell box's samples
// 1.12x faster on llvmpipe (docs/performance-history/round-05.md). atan2Accurate(0, 0) = 0.
float atan2Accurate(float y, float x) {
    float ax = abs(x), ay = abs(y);
    float lo = min(ax, ay), hi = max(ax, ay);
    bool reduce = lo > 0.41421356237309505 * hi;  // tan(pi/8): atan(a) = pi/4 + atan((a - 1) / (a + 1))
    float t = hi > 0.0 ? (reduce ? lo - hi : lo) / (reduce ? lo + hi : hi) : 0.0;
    float z = t * t;
    float r = (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z - 3.33329491539e-1) * z * t + t;
    r += reduce ? 0.25 * PI : 0.0;     // atan(lo / hi), in [0, pi/4]
    r = ay > ax ? 0.5 * PI - r : r;    // atan(ay / ax), in [0, pi/2]
    r = x < 0.0 ? PI - r : r;          // in [0, pi]
    return y < 0.0 ? -r : r;
}

#endif
