// Merging the AOV layers of partial renders (penumbra merge; SCENE_FORMAT.md "AOVs (v3)"):
// each layer combined so that the merge is the layer one render of all the samples would
// have had. image/merge.cpp merges the image and checks the headers; this file, the layers.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "image/image.h"

namespace penumbra {

// The inputs' AOV lists (names, in order; from their headers) must be the same: a layer
// that some pieces lack cannot be merged. Throws InputError naming the first that differs.
void checkMergeAovLists(const std::vector<Image>& images, const std::function<std::string(size_t)>& nameOf);

// The merged layers of `images` (same size and lists, checked), in their order:
// - albedo, normal, position: the penumbra:spp-weighted mean, as the image (each is a mean
//   over all of its render's samples);
// - depth: the spp-weighted mean over the pieces whose depth is finite, +inf where none
//   is (a piece's depth is a mean over its samples that hit, whose number the file does
//   not hold: exact where every sample of the pixel hits or none does, see
//   docs/SCENE_FORMAT.md);
// - variance: the variance estimate one render of all the samples gives (pooled from
//   each piece's mean and variance, see merge_aovs.cpp);
// - ids: the same in every piece (they come from the pixel's centre ray), else refused.
// Throws InputError naming the file and pixel of a value no render writes (NaN, a negative
// variance or depth) or of ids that differ from the first input's.
std::vector<AovLayer> mergeAovLayers(const std::vector<Image>& images,
                                     const std::function<std::string(size_t)>& nameOf);

}  // namespace penumbra
