// The preview's tone map: the mean of each pixel's accumulated samples (sum / count),
// times 2^exposure, through the clamp or filmic curve (host/image/tone_map.cpp, the same
// operations), encoded with the exact sRGB OETF (IEC 61966-2-1, the same formula and
// rounding as linearToSrgb8 in host/image/png.cpp), packed as RGBA8 bytes.
// The host copies the packed pixels into an image and blits that to the window.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/types.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = TONEMAP_BINDING_ACCUM) readonly buffer Accumulation { AccumSum accum[]; };
layout(std430, binding = TONEMAP_BINDING_COMPENSATION) readonly buffer Compensation {
    AccumCompensation accumCompensation[];
};
layout(std430, binding = TONEMAP_BINDING_PIXELS) writeonly buffer Pixels { uint pixels[]; };
layout(push_constant) uniform Constants { ToneMapConstants toneMap; };

// One linear value to an 8-bit sRGB code; !(x > 0) also sends NaN to black.
uint linearToSrgb8(float linear) {
    if (!(linear > 0.0)) return 0u;
    if (linear >= 1.0) return 255u;
    float encoded = linear < 0.0031308 ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
    return min(uint(floor(encoded * 255.0 + 0.5)), 255u);
}

// Narkowicz's ACES fit, as acesFilmic in host/image/tone_map.cpp (cited there).
float acesFilmic(float x) {
    if (!(x > 0.0)) return 0.0;
    if (x > 1e10) return 1.0;
    float y = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
    return clamp(y, 0.0, 1.0);
}

float applyToneCurve(float linear, uint curve) {
    if (curve == 1u) return acesFilmic(linear);
    if (!(linear > 0.0)) return 0.0;
    return min(linear, 1.0);
}

uint encode(float linear, uint curve) { return linearToSrgb8(applyToneCurve(linear, curve)); }

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= toneMap.width || pixel.y >= toneMap.height) return;
    uint index = pixel.y * toneMap.width + pixel.x;
    // The compensated sum's mean (shared/types.h, AccumSum), as Renderer::readback.
    AccumSum sum = accum[index];
    vec3 compensation = accumCompensation[index].compensation;
    vec3 mean = sum.count > 0u ? (sum.sum - compensation) / float(sum.count) : vec3(0.0);
    vec3 scaled = mean * toneMap.scale;
    uint c = toneMap.curve;
    pixels[index] = encode(scaled.r, c) | (encode(scaled.g, c) << 8) | (encode(scaled.b, c) << 16) | (255u << 24);
}
