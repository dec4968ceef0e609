// AOV layer -> displayable colours (see aov_false_color.h).
#include "image/aov_false_color.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "image/image_file.h"  // srgbToLinear

namespace penumbra {

namespace {

constexpr uint32_t kNoId = 4294967295u;

// A well-mixed 32-bit hash (Chris Wellons' "lowbias32", https://nullprogram.com/blog/2018/07/31/),
// so that neighbouring ids get unrelated colours.
uint32_t hashId(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// Each channel's [min, max] over the finite values of a layer of `channels` floats a pixel.
void finiteRange(const AovLayer& layer, size_t channels, std::vector<float>& lo, std::vector<float>& hi) {
    lo.assign(channels, std::numeric_limits<float>::infinity());
    hi.assign(channels, -std::numeric_limits<float>::infinity());
    for (size_t k = 0; k < layer.floats.size(); ++k)
        if (std::isfinite(layer.floats[k])) {
            lo[k % channels] = std::min(lo[k % channels], layer.floats[k]);
            hi[k % channels] = std::max(hi[k % channels], layer.floats[k]);
        }
}

// 0 where the layer holds one value alone.
float scaled(float v, float lo, float hi) { return hi > lo ? (v - lo) / (hi - lo) : 0.0f; }

}  // namespace

std::vector<float> aovFalseColor(const AovLayer& layer, size_t pixels) {
    std::vector<float> rgb(pixels * 3, 0.0f);
    if (!layer.ids.empty()) {
        for (size_t i = 0; i < pixels; ++i) {
            if (layer.ids[i] == kNoId) continue;
            const uint32_t h = hashId(layer.ids[i] + 1u);  // + 1: the hash maps 0 to 0, a grey
            // Display values in [0.25, 1]: no id is as dark as a miss.
            for (int c = 0; c < 3; ++c)
                rgb[3 * i + c] = srgbToLinear(0.25f + 0.75f * float((h >> (8 * c)) & 255u) / 255.0f);
        }
        return rgb;
    }
    const size_t n = layer.channels.size();
    std::vector<float> lo, hi;
    finiteRange(layer, n, lo, hi);
    for (size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = layer.floats[i * n + std::min<size_t>(c, n - 1)];
            const size_t ch = std::min<size_t>(c, n - 1);
            float display;
            if (layer.name == "albedo") {
                rgb[3 * i + c] = std::clamp(v, 0.0f, 1.0f);
                continue;
            } else if (layer.name == "normal") {
                display = v * 0.5f + 0.5f;
            } else if (layer.name == "depth") {
                display = std::isfinite(v) ? 1.0f - scaled(v, lo[0], hi[0]) : 0.0f;
            } else if (layer.name == "variance") {
                display = hi[ch] > 0 ? std::sqrt(std::max(v, 0.0f) / hi[ch]) : 0.0f;
            } else {  // position
                display = scaled(v, lo[ch], hi[ch]);
            }
            rgb[3 * i + c] = srgbToLinear(std::clamp(display, 0.0f, 1.0f));
        }
    return rgb;
}

}  // namespace penumbra
