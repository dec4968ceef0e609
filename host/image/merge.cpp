// Merging partial renders (penumbra merge): the spp-weighted mean of images rendered
// with the same scene, each an unbiased estimate from its own samples. Refuses inputs
// whose average would not be such an estimate (SCENE_FORMAT.md, "Output").
#include <algorithm>
#include <climits>
#include <string>

#include "core/errors.h"
#include "image/image.h"

namespace penumbra {

namespace {

std::string sizeText(const Image& image) { return std::to_string(image.width) + "x" + std::to_string(image.height); }

// A render without penumbra:sampler predates the sampler option: it used independent samples.
std::string samplerOf(const Image& image) { return image.meta.sampler.value_or("independent"); }

}  // namespace

Image mergeImages(const std::vector<Image>& images, const std::vector<std::string>& names) {
    auto nameOf = [&](size_t i) { return i < names.size() ? names[i] : "image " + std::to_string(i + 1); };
    if (images.empty()) throw InputError("merge: no images given");

    const Image& first = images[0];
    int64_t totalSpp = 0;
    for (size_t i = 0; i < images.size(); ++i) {
        const Image& image = images[i];
        // Without spp the weight is unknown, so the mean would be silently wrong.
        if (!image.meta.spp || *image.meta.spp <= 0)
            throwInputError(nameOf(i), "", "missing penumbra:spp attribute; only penumbra renders can be merged");
        if (image.width != first.width || image.height != first.height)
            throwInputError(nameOf(i), "",
                            "size " + sizeText(image) + " differs from " + nameOf(0) + " (" + sizeText(first) + ")");
        if (image.meta.integrator && first.meta.integrator && *image.meta.integrator != *first.meta.integrator)
            throwInputError(nameOf(i), "",
                            "integrator differs from " + nameOf(0) +
                                "'s; merging renders of different integrators is not meaningful");
        // Partials of one render share its sampler: only then is the merge the same image as
        // one render of all the samples (and a Sobol' render's aligned blocks stay nets).
        if (samplerOf(image) != samplerOf(first))
            throwInputError(nameOf(i), "",
                            "sampler " + samplerOf(image) + " differs from " + nameOf(0) + "'s (" + samplerOf(first) +
                                "); render all partials with the same sampler.type");
        totalSpp += *image.meta.spp;
    }
    if (totalSpp > INT_MAX) throw InputError("merge: total spp " + std::to_string(totalSpp) + " exceeds " + std::to_string(INT_MAX));

    // Same seed and overlapping sample indices means the same random numbers were used
    // twice: the partials are correlated and their mean has the variance of fewer samples.
    // Each input covers its penumbra:pieces (a merged file), else the one piece of its
    // seed, sample_offset (absent: the scene default, 0) and spp. Without a seed nothing
    // can be checked (nor recorded).
    std::vector<std::vector<SamplePiece>> pieces(images.size());
    bool allKnown = true;
    for (size_t i = 0; i < images.size(); ++i) {
        pieces[i] = samplePiecesOf(images[i].meta);
        allKnown = allKnown && !pieces[i].empty();
        int64_t covered = 0;
        for (const SamplePiece& p : pieces[i]) covered += p.end - p.first;
        if (images[i].meta.pieces && covered != *images[i].meta.spp)
            throwInputError(nameOf(i), "",
                            "penumbra:pieces covers " + std::to_string(covered) + " samples but penumbra:spp is " +
                                std::to_string(*images[i].meta.spp));
    }
    for (size_t i = 0; i < images.size(); ++i) {
        for (size_t j = i + 1; j < images.size(); ++j) {
            for (const SamplePiece& a : pieces[i]) {
                for (const SamplePiece& b : pieces[j]) {
                    if (a.seed != b.seed) continue;
                    const int64_t begin = std::max(a.first, b.first), end = std::min(a.end, b.end);
                    if (begin < end)
                        throwInputError(nameOf(j), "",
                                        "sample indices [" + std::to_string(begin) + ", " + std::to_string(end) +
                                            ") overlap with " + nameOf(i) + " (both seed " + std::to_string(a.seed) +
                                            "); such partials are not independent, render them with disjoint "
                                            "sampler.sample_offset ranges");
                }
            }
        }
    }

    Image result;
    result.width = first.width;
    result.height = first.height;
    result.rgb.resize(first.rgb.size());
    for (size_t k = 0; k < result.rgb.size(); ++k) {
        double sum = 0;
        for (const Image& image : images) sum += double(*image.meta.spp) * image.rgb[k];
        result.rgb[k] = float(sum / double(totalSpp));
    }

    ImageMetadata& m = result.meta;
    m.spp = int(totalSpp);
    m.seed = first.meta.seed;
    m.integrator = first.meta.integrator;
    m.sampler = first.meta.sampler;
    if (allKnown) {
        std::vector<SamplePiece> all;
        for (const auto& p : pieces) all.insert(all.end(), p.begin(), p.end());
        m.pieces = normalizeSamplePieces(std::move(all));
    }
    for (const Image& image : images) {
        if (image.meta.sampleOffset) m.sampleOffset = std::min(m.sampleOffset.value_or(INT_MAX), *image.meta.sampleOffset);
        if (image.meta.renderSeconds) m.renderSeconds = m.renderSeconds.value_or(0.0) + *image.meta.renderSeconds;
    }
    return result;
}

}  // namespace penumbra
