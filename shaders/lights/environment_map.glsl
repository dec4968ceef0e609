// Environment map (SCENE_FORMAT.md `environment` with `file`): the radiance lookup, the
// importance sampling in proportion to texel luminance times texel solid angle (one alias
// table over all texels, PBR book 4th ed. 12.5.2's piecewise-constant distribution) and its
// solid-angle pdf. Mirrors host/render/environment_map.cpp, which the tests compare against.
#ifndef PENUMBRA_LIGHTS_ENVIRONMENT_MAP_GLSL
#define PENUMBRA_LIGHTS_ENVIRONMENT_MAP_GLSL

#include "common/math.glsl"
#include "sampling/warp.glsl"
#include "lights/light_sample.glsl"
#include "lights/light_data.glsl"

uint environmentMapWidth(Light light) { return light.first; }
uint environmentMapHeight(Light light) { return light.count; }

// The texel (column, row) that radiance from unit direction d is read from: u =
// atan2(d.x, -d.z) / (2 pi) wrapped to [0, 1), v = theta / pi, column floor(u W), row
// floor(v H). theta is atan(|d.xz|, d.y) rather than the contract's acos(d.y): the same angle,
// but exact to float precision near the poles, where acos of a float loses the rows. Both
// through atan2Accurate: lavapipe's atan is off by ~2e-5, a fortieth of an 8k map's column.
uvec2 environmentMapTexel(vec3 d, uint w, uint h) {
    float u = atan2Accurate(d.x, -d.z) * INV_TWO_PI;
    u -= floor(u);
    float v = atan2Accurate(length(d.xz), d.y) * INV_PI;
    return uvec2(min(uint(u * float(w)), w - 1u), min(uint(v * float(h)), h - 1u));
}

// cos(theta_row) - cos(theta_row+1) with theta = pi row / H, as 2 sin(mid) sin(half step)
// (the difference of two cosines near 1 would cancel in float near the poles).
float environmentRowCosineSpan(uint row, uint h) {
    float step = PI / float(h);
    return 2.0 * sin((float(row) + 0.5) * step) * sin(0.5 * step);
}

// Solid angle of a texel of row `row`: (2 pi / W) (cos theta_row - cos theta_row+1).
float environmentTexelSolidAngle(uint row, uint w, uint h) {
    return TWO_PI / float(w) * environmentRowCosineSpan(row, h);
}

vec3 environmentMapRadiance(Light light, vec3 wi) {
    uint w = environmentMapWidth(light);
    uvec2 t = environmentMapTexel(wi, w, environmentMapHeight(light));
    return loadEnvironmentTexel(t.y * w + t.x);
}

// Slot and coin of an alias draw over `count` entries from the 48 bits of two uniform numbers
// of 24 bits each (common/rng.glsl's resolution): slot + coin = (a 2^24 + b) count / 2^48 with
// a = u.x 2^24, b = u.y 2^24. One 24-bit number would reach only 2^24 slots, and for counts
// that do not divide 2^24 some slots more often than others (an 8k x 4k map has 2^25 texels).
// The coin is the fraction's top 24 bits. Products in 64 bits through umulExtended.
uint environmentAliasSlot(vec2 u, uint count, out float coin) {
    uint a = uint(u.x * 16777216.0), b = uint(u.y * 16777216.0);
    uint pHi, pLo, qHi, qLo;
    umulExtended(a, count, pHi, pLo);
    umulExtended(b, count, qHi, qLo);
    uint sum = (pLo & 0xffffffu) + ((qHi << 8) | (qLo >> 24));  // (a count mod 2^24) + floor(b count / 2^24)
    uint slot = ((pHi << 8) | (pLo >> 24)) + (sum >> 24);       // floor(a count / 2^24) + carry
    coin = float(sum & 0xffffffu) * (1.0 / 16777216.0);
    return min(slot, count - 1u);
}

// A texel from the alias table with u.xy (slot and coin), then a direction uniform in its
// solid angle: phi uniform over its column (the coin, rescaled to [0, 1) within the side it
// fell on: uniform again), cos theta uniform over its row (u.z).
// pdf = pmf(texel) / solid angle (a black map's table is uniform in solid angle).
bool sampleEnvironmentMap(Light light, vec3 u, inout LightSample ls) {
    uint w = environmentMapWidth(light), h = environmentMapHeight(light);
    float coin;
    AliasEntry e = loadEnvironmentAlias(environmentAliasSlot(u.xy, w * h, coin));
    float within = remapAfterChoice(coin, e.probability);  // sampling/warp.glsl
    if (coin >= e.probability) e = loadEnvironmentAlias(e.alias);
    uint col = e.item % w, row = e.item / w;
    float phi = TWO_PI * (float(col) + within) / float(w);
    // 1 - cos theta, from the row's top edge 2 sin^2(theta_row / 2) down u.z of the row's span.
    float halfTop = 0.5 * PI * float(row) / float(h);
    float oneMinusCos = 2.0 * sin(halfTop) * sin(halfTop) + u.z * environmentRowCosineSpan(row, h);
    float cosTheta = 1.0 - oneMinusCos;
    float sinTheta = sqrt(max(0.0, oneMinusCos * (2.0 - oneMinusCos)));
    ls.wi = vec3(sinTheta * sin(phi), cosTheta, -sinTheta * cos(phi));
    ls.pdf = e.pmf / environmentTexelSolidAngle(row, w, h);
    ls.radiance = loadEnvironmentTexel(e.item);
    return ls.pdf > 0.0;
}

// The solid-angle density of wi under sampleEnvironmentMap: pmf of the texel wi is looked up
// in, over that texel's solid angle (constant over the texel, consistent with the lookup).
float environmentMapPdf(Light light, vec3 wi) {
    uint w = environmentMapWidth(light), h = environmentMapHeight(light);
    uvec2 t = environmentMapTexel(wi, w, h);
    return loadEnvironmentAlias(t.y * w + t.x).pmf / environmentTexelSolidAngle(t.y, w, h);
}

#endif
