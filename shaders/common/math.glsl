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

// atan(y, x) to about float precision. Vulkan lets atan be off by 4096 ULP and lavapipe's is
// off by ~2e-5 relative (measured through the solid angles of sampling/spherical_*.glsl,
// whose pdfs integrated to 1 + 2e-5): one Newton step on y cos(t) - x sin(t) = 0 from the
// built-in's estimate removes that (the error becomes quadratic in the first one's).
float atan2Accurate(float y, float x) {
    float t = atan(y, x);
    float c = cos(t), s = sin(t);
    float den = x * c + y * s;  // = |(x, y)| cos(error), never 0 once (x, y) != 0
    return den > 0.0 ? t + (y * c - x * s) / den : t;
}

#endif
