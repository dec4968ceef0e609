// Tone curves (see tone_map.h). Kept operation for operation as tonemap.comp's.
#include "image/tone_map.h"

#include <algorithm>

namespace penumbra {

std::optional<ToneCurve> toneCurveFromName(const std::string& name) {
    if (name == "clamp") return ToneCurve::Clamp;
    if (name == "filmic") return ToneCurve::Filmic;
    return std::nullopt;
}

const char* toneCurveName(ToneCurve curve) { return curve == ToneCurve::Filmic ? "filmic" : "clamp"; }

float acesFilmic(float x) {
    if (!(x > 0.0f)) return 0.0f;
    // The rational curve overflows to inf/inf for huge x; its limit there is 2.51/2.43 > 1.
    if (x > 1e10f) return 1.0f;
    const float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
    return std::clamp(y, 0.0f, 1.0f);
}

float applyToneCurve(float linear, ToneCurve curve) {
    if (curve == ToneCurve::Filmic) return acesFilmic(linear);
    if (!(linear > 0.0f)) return 0.0f;
    return std::min(linear, 1.0f);
}

}  // namespace penumbra
