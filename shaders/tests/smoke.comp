// Smallest possible kernel: out[i] = 2 i + push.add. Proves the build embeds SPIR-V and the
// GPU plumbing (pipeline, descriptors, push constants, readback) works.
#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly restrict buffer Out { uint values[]; };
layout(push_constant) uniform Push { uint add; uint count; };
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < count) values[i] = 2u * i + add;
}
