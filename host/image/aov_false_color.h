// How an AOV layer is shown (the preview's layer key, docs/guide/preview.md; the dataset
// example's grid, penumbra.false_color): a picture of each layer whose values are not
// radiance. One home for the mapping, used by the preview and the Python module.
#pragma once

#include <cstddef>
#include <vector>

#include "image/image.h"

namespace penumbra {

// `layer` (of `pixels` pixels) as linear RGB, 3 floats a pixel in [0, 1], chosen so that
// the sRGB encoding at exposure 0 with the clamp curve (writePng, the preview) shows:
// - albedo: itself (a linear colour already);
// - normal: n * 0.5 + 0.5 (the usual normal-map colours; a miss, n = 0, is grey);
// - position: each axis scaled to [0, 1] over the layer's range;
// - depth: 1 at the nearest hit down to 0 at the farthest, +inf (a miss) black;
// - variance: the standard deviation over the layer's largest, per channel;
// - ids: a colour hashed from the id (the same id, the same colour, in every frame), a miss
//   (4294967295) black.
std::vector<float> aovFalseColor(const AovLayer& layer, size_t pixels);

}  // namespace penumbra
