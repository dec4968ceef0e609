// Test entry point for bsdf/bsdf.glsl: draws BRDF samples with the stateless rng, evaluates
// bsdfPdf at given directions and bsdfEval at given direction pairs, so the host can run
// chi-square, reciprocity and energy tests against the GLSL itself.
// Interface: tests/bsdf_sampling_test.h.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "shared/types.h"
#include "common/rng.glsl"
#include "bsdf/bsdf.glsl"
#include "tests/bsdf_sampling_test.h"

layout(local_size_x = BSDF_TEST_WORKGROUP_SIZE) in;
layout(std430, binding = 0) readonly restrict buffer Inputs { BsdfTestRecord inputs[]; };
layout(std430, binding = 1) writeonly restrict buffer Outputs { BsdfTestRecord outputs[]; };
layout(push_constant) uniform PushBlock { BsdfTestPush push; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    Material m = push.material;
    BsdfTestRecord r;
    r.a = vec4(0.0);
    r.b = vec4(0.0);
    if (push.mode == BSDF_TEST_MODE_SAMPLE) {
        Rng rng = makeRng(0u, i, push.seed);
        vec3 wi;
        BsdfValue value;
        // As the integrator draws (direct.comp, bsdfSampleEstimate): one pair, whose first
        // number also picks the lobe.
        if (bsdfSample(m, push.n, push.wo, rand2(rng), wi, value)) {
            r.a = vec4(wi, value.pdf);
            r.b.x = bsdfPdf(m, push.n, push.wo, wi);
            r.b.yzw = value.f - bsdfEval(m, push.n, push.wo, wi);
        }
    } else if (push.mode == BSDF_TEST_MODE_PDF) {
        r.a.x = bsdfPdf(m, push.n, push.wo, inputs[i].a.xyz);
    } else {
        vec3 wo = inputs[i].a.xyz, wi = inputs[i].b.xyz;
        r.a.xyz = bsdfEval(m, push.n, wo, wi);
        r.b.xyz = bsdfEval(m, push.n, wi, wo);
    }
    outputs[i] = r;
}
