// How linear radiance becomes a displayable value in [0, 1] before the sRGB encoding, for
// PNGs and the preview (SCENE_FORMAT.md "Output": --exposure EV, --tonemap clamp|filmic).
// The EXR is never tone mapped. shaders/preview/tonemap.comp applies the same curves.
#pragma once

#include <optional>
#include <string>

namespace penumbra {

// The values match ToneMapConstants.curve (shaders/shared/types.h).
enum class ToneCurve : unsigned { Clamp = 0, Filmic = 1 };

// What a PNG or the preview shows: radiance times 2^exposure, then the curve.
struct ToneLook {
    float exposure = 0.0f;  // in stops (EV)
    ToneCurve curve = ToneCurve::Clamp;
};

// "clamp" / "filmic" and back; nullopt for any other name.
std::optional<ToneCurve> toneCurveFromName(const std::string& name);
const char* toneCurveName(ToneCurve curve);

// Narkowicz's fit of the ACES filmic curve (RRT + ODT), "ACES Filmic Tone Mapping Curve",
// https://knarkowicz.wordpress.com/2016/01/06/aces-filmic-tone-mapping-curve/ :
// x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1]. Near-linear with a toe
// at the dark end (slope 0.21 at 0; 0.80 at x = 1) and a shoulder that reaches 1 at x = 7.24, so highlights
// roll off instead of clipping. !(x > 0), NaN included, gives 0.
float acesFilmic(float x);

// The display value in [0, 1] of `linear` (already times 2^exposure) under `curve`.
float applyToneCurve(float linear, ToneCurve curve);

}  // namespace penumbra
