// Test entry point for lights/light_flat.glsl, the flat form of a small light tree, with the
// leaves as specialization constants as the render kernels get them: the pmf of every leaf
// at a shading point, and draws with the stateless rng, whose pmfs the host compares with
// its own (host/render/light_flat.h). The interface is the light-BVH test kernel's
// (tests/light_bvh_test.h), with leaves for items; a draw's replay goes through the leaf's
// hit primitive, as MIS finds it again, where it has one.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "shared/types.h"
#include "common/rng.glsl"
#include "lights/light_flat.glsl"
#include "tests/light_bvh_test.h"

layout(local_size_x = LIGHT_BVH_TEST_WORKGROUP_SIZE) in;
layout(std430, binding = LIGHT_BVH_TEST_BINDING_OUT) writeonly restrict buffer Records { LightBvhTestRecord records[]; };
layout(push_constant) uniform PushBlock { LightBvhTestPush push; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    LightBvhTestRecord r;
    r.item = i;
    r.pmf = 0.0;
    r.replayed = 0.0;
    r.pad = 0.0;
    if (push.mode == LIGHT_BVH_TEST_MODE_PMF) {
        r.pmf = lightFlatPmf(push.p, push.n, i);
    } else {
        Rng rng = makeRng(0u, i, push.seed);
        r.item = sampleLightFlat(push.p, push.n, rand1(rng), r.pmf);
        uint hitPrimitive = lightFlatHitPrimitive(r.item);
        r.replayed = lightFlatPmf(push.p, push.n, hitPrimitive == NO_HIT ? r.item : lightFlatLeafHitBy(hitPrimitive));
        // The leaf's light (high 16 bits) and item primitive (low 16 bits) as float bits.
        r.pad = uintBitsToFloat((lightFlatLight(r.item) << 16u) | (lightFlatPrimitive(r.item) & 0xffffu));
    }
    records[i] = r;
}
