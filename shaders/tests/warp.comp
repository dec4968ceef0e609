// Test entry point for shaders/sampling/warp.glsl: draws samples of one warp with the
// stateless rng, or evaluates that warp's pdf at given points, so the host can run a
// chi-square test (tests/chi2.h) against the GLSL pdf itself. Interface: tests/warp_test.h.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "common/rng.glsl"
#include "sampling/warp.glsl"
#include "tests/warp_test.h"

layout(local_size_x = WARP_WORKGROUP_SIZE) in;
layout(std430, binding = 0) readonly restrict buffer Points { vec4 points[]; };
layout(std430, binding = 1) writeonly restrict buffer Results { vec4 results[]; };
layout(push_constant) uniform PushBlock { WarpPush push; };

// The warp's sample of u, with its pdf in .w (evaluated by the pdf function at the sample).
vec4 sampleWarp(uint warp, vec2 u, float param) {
    if (warp == WARP_UNIFORM_HEMISPHERE) {
        vec3 v = squareToUniformHemisphere(u);
        return vec4(v, uniformHemispherePdf(v));
    }
    if (warp == WARP_COSINE_HEMISPHERE) {
        vec3 v = squareToCosineHemisphere(u);
        return vec4(v, cosineHemispherePdf(v.z));
    }
    if (warp == WARP_PHONG_LOBE) {
        vec3 v = squareToPhongLobe(u, param);
        return vec4(v, phongLobePdf(v.z, param));
    }
    if (warp == WARP_UNIFORM_SPHERE) return vec4(squareToUniformSphere(u), uniformSpherePdf());
    if (warp == WARP_UNIFORM_CONE) {
        vec3 v = squareToUniformCone(u, param);
        return vec4(v, uniformConeContains(v, 1.0 - param) ? uniformConePdf(param) : 0.0);
    }
    if (warp == WARP_UNIFORM_CONE_1M) {
        vec3 v = squareToUniformConeOneMinusCos(u, param);
        return vec4(v, uniformConeContains(v, param) ? uniformConePdfOneMinusCos(param) : 0.0);
    }
    if (warp == WARP_UNIFORM_DISK) {
        vec2 p = squareToUniformDisk(u);
        return vec4(p, 0.0, uniformDiskPdf(p));
    }
    if (warp == WARP_UNIFORM_TRIANGLE) {
        vec3 b = squareToUniformTriangle(u);
        return vec4(b, all(greaterThanEqual(b, vec3(0.0))) ? uniformTrianglePdf(param) : 0.0);
    }
    return vec4(0.0);
}

// The warp's pdf at point p (a unit direction, a disk point in .xy, or barycentrics).
float warpPdf(uint warp, vec3 p, float param) {
    if (warp == WARP_UNIFORM_HEMISPHERE) return uniformHemispherePdf(p);
    if (warp == WARP_COSINE_HEMISPHERE) return cosineHemispherePdf(p.z);
    if (warp == WARP_PHONG_LOBE) return phongLobePdf(p.z, param);
    if (warp == WARP_UNIFORM_SPHERE) return uniformSpherePdf();
    if (warp == WARP_UNIFORM_CONE) return uniformConeContains(p, 1.0 - param) ? uniformConePdf(param) : 0.0;
    if (warp == WARP_UNIFORM_CONE_1M) return uniformConeContains(p, param) ? uniformConePdfOneMinusCos(param) : 0.0;
    if (warp == WARP_UNIFORM_DISK) return uniformDiskPdf(p.xy);
    if (warp == WARP_UNIFORM_TRIANGLE)
        return all(greaterThanEqual(p, vec3(0.0))) ? uniformTrianglePdf(param) : 0.0;
    return 0.0;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    if (push.mode == WARP_MODE_SAMPLE) {
        Rng rng = makeRng(0u, i, push.seed);
        results[i] = sampleWarp(push.warp, rand2(rng), push.param);
    } else {
        results[i] = vec4(warpPdf(push.warp, points[i].xyz, push.param), 0.0, 0.0, 0.0);
    }
}
