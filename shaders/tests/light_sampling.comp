// Test entry point for lights/lights.glsl: draws light samples with the stateless rng,
// evaluates lightPdf the way the integrator does (trace, then the pdf at the first hit),
// and draws from the selection tables, so the host can run chi-square tests against the
// GLSL itself. Binds the scene buffers at the render kernels' BINDING_* numbers (through
// the includes) and its own buffers after them. Interface: tests/light_sampling_test.h.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "shared/types.h"
#include "common/math.glsl"
#include "common/rng.glsl"
#include "geometry/bvh.glsl"
#include "geometry/surface.glsl"
#include "lights/lights.glsl"
#include "tests/light_sampling_test.h"

layout(local_size_x = LIGHT_TEST_WORKGROUP_SIZE) in;
layout(std430, binding = LIGHT_TEST_BINDING_IN) readonly restrict buffer Directions { vec4 directions[]; };
layout(std430, binding = LIGHT_TEST_BINDING_OUT) writeonly restrict buffer Records { LightTestRecord records[]; };
layout(push_constant) uniform PushBlock { LightTestPush push; };

uvec2 bvhBesideRange() { return uvec2(push.besideFirst, push.besideCount); }

LightSamplingModes testModes() {
    return LightSamplingModes(push.sphereSampling, push.quadSampling, push.triangleSampling, push.minSolidAngle,
                              push.minElevationSine);
}

// The density of wi as the integrator evaluates it for a BSDF-sampled ray: the first hit
// along x + t wi must belong to the light, and lightPdf is taken there with the hit's
// geometric (front) normal and distance. The environment is "hit" when the ray escapes,
// and has no geometry: lightPdf directly. Delta lights cannot be hit (lightPdf says 0).
float tracedLightPdf(uint index, vec3 x, vec3 n, vec3 wi, out float t, out uint primitive, out bool hitLight) {
    LightSamplingModes modes = testModes();
    t = 0.0;
    primitive = NO_HIT;
    hitLight = false;
    uint type = loadLight(index).type;
    if (type == LIGHT_POINT || type == LIGHT_DIRECTIONAL)
        return lightPdf(index, x, n, wi, vec3(0.0), vec3(0.0), 0.0, NO_HIT, modes);
    Hit hit;
    bool found = traceClosest(x, wi, FLOAT_MAX, hit);
    if (type == LIGHT_ENVIRONMENT) {
        hitLight = !found;
        return found ? 0.0 : lightPdf(index, x, n, wi, vec3(0.0), vec3(0.0), 0.0, NO_HIT, modes);
    }
    if (!found) return 0.0;
    t = hit.t;
    primitive = hit.primitive;
    SurfacePoint y = surfaceAt(hit, x, wi);
    if (y.light != index) return 0.0;
    hitLight = true;
    return lightPdf(index, x, n, wi, y.position, y.geometricNormal, hit.t, hit.primitive, modes);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    LightTestRecord r;
    r.wi = vec3(0.0);
    r.pdf = 0.0;
    r.radiance = vec3(0.0);
    r.dist = 0.0;
    r.tracedPdf = 0.0;
    r.tracedT = 0.0;
    r.hitPrimitive = NO_HIT;
    r.flags = 0u;
    if (push.mode == LIGHT_TEST_MODE_SAMPLE) {
        Rng rng = makeRng(0u, i, push.seed);
        vec3 u = vec3(rand2(rng), rand1(rng));  // three uniform numbers, as drawLight gives (direct.comp)
        LightSample ls;
        if (sampleLight(push.light, push.x, push.n, u,
                        testModes(), ls)) {
            r.wi = ls.wi;
            r.pdf = ls.pdf;
            r.radiance = ls.radiance;
            r.dist = ls.dist;
            r.flags = LIGHT_TEST_ACCEPTED | (ls.isDelta ? LIGHT_TEST_DELTA : 0u);
            bool hitLight;
            r.tracedPdf = tracedLightPdf(push.light, push.x, push.n, ls.wi, r.tracedT, r.hitPrimitive, hitLight);
            if (hitLight) r.flags |= LIGHT_TEST_HIT_LIGHT;
        }
    } else if (push.mode == LIGHT_TEST_MODE_PDF) {
        float t;
        uint primitive;
        bool hitLight;
        r.pdf = tracedLightPdf(push.light, push.x, push.n, directions[i].xyz, t, primitive, hitLight);
        r.tracedT = t;
        r.hitPrimitive = primitive;
        r.flags = hitLight ? LIGHT_TEST_HIT_LIGHT : 0u;
    } else {
        Rng rng = makeRng(0u, i, push.seed);
        float pmf;
        uint item;
        if (push.table == LIGHT_TEST_TABLE_LIGHTS) {
            float rest;
            item = selectLight(push.tableOffset, push.tableCount, rand2Bits(rng).x, pmf, rest);
            r.tracedT = rest;
        } else {
            AliasEntry e = sampleAlias(push.tableOffset, push.tableCount, rand1(rng), true);
            item = e.item;
            pmf = e.pmf;
        }
        r.hitPrimitive = item;
        r.tracedPdf = pmf;
    }
    records[i] = r;
}
