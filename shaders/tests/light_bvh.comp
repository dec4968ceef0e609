// Test entry point for lights/light_bvh.glsl: the tree's pmf of every item at a shading
// point, and descents with the stateless rng, so that the host can compare the GPU's
// importance, descent and replay with its own (host/render/light_bvh.h). Interface:
// tests/light_bvh_test.h.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "shared/types.h"
#include "common/rng.glsl"
#include "lights/light_bvh.glsl"
#include "tests/light_bvh_test.h"

layout(local_size_x = LIGHT_BVH_TEST_WORKGROUP_SIZE) in;
layout(std430, binding = LIGHT_BVH_TEST_BINDING_OUT) writeonly restrict buffer Records { LightBvhTestRecord records[]; };
layout(push_constant) uniform PushBlock { LightBvhTestPush push; };

uvec2 itemTrail(uint item) {
    LightBvhItem it = loadLightBvhItem(push.itemsTexel, item);
    return uvec2(it.trailLow, it.trailHigh);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    LightBvhTestRecord r;
    r.item = i;
    r.pmf = 0.0;
    r.replayed = 0.0;
    r.pad = 0.0;
    if (push.mode == LIGHT_BVH_TEST_MODE_PMF) {
        r.pmf = lightBvhTreePmf(push.p, push.n, itemTrail(i));
    } else {
        Rng rng = makeRng(0u, i, push.seed);
        float rest;
        r.item = sampleLightBvhTree(push.p, push.n, rand1(rng), r.pmf, rest);
        r.replayed = lightBvhTreePmf(push.p, push.n, itemTrail(r.item));
    }
    records[i] = r;
}
