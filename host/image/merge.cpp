// Merging partial renders (penumbra merge): the spp-weighted mean of images rendered
// with the same scene, each an unbiased estimate from its own samples. Refuses inputs
// whose average would not be such an estimate (SCENE_FORMAT.md, "Output").
#include <algorithm>
#include <climits>
#include <limits>
#include <string>

#include "core/errors.h"
#include "image/image.h"
#include "image/merge_aovs.h"

namespace penumbra {

namespace {

std::string sizeText(const Image& image) { return std::to_string(image.width) + "x" + std::to_string(image.height); }

// A render without penumbra:sampler predates the sampler option: it used independent samples.
std::string samplerOf(const Image& image) { return image.meta.sampler.value_or("independent"); }

}  // namespace

void checkMergeHeaders(const std::vector<Image>& images, const std::vector<std::string>& names) {
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
    checkMergeAovLists(images, nameOf);
    if (totalSpp > INT_MAX) throw InputError("merge: total spp " + std::to_string(totalSpp) + " exceeds " + std::to_string(INT_MAX));

    // Same seed and overlapping sample indices means the same random numbers were used
    // twice: the partials are correlated and their mean has the variance of fewer samples.
    // Each input covers its penumbra:pieces (a merged file), else the one piece of its
    // seed, sample_offset (absent: the scene default, 0) and spp. Without a seed nothing
    // can be checked (nor recorded).
    std::vector<std::vector<SamplePiece>> pieces(images.size());
    for (size_t i = 0; i < images.size(); ++i) {
        pieces[i] = samplePiecesOf(images[i].meta);
        int64_t covered = 0;
        for (const SamplePiece& p : pieces[i]) covered += p.end - p.first;
        if (images[i].meta.pieces && covered != *images[i].meta.spp)
            throwInputError(nameOf(i), "",
                            "penumbra:pieces covers " + std::to_string(covered) + " samples but penumbra:spp is " +
                                std::to_string(*images[i].meta.spp));
    }
    // All pieces sorted by (seed, first): a piece overlaps an earlier one exactly when it
    // starts before the furthest end seen so far in its seed (n log n; comparing every pair
    // took a minute for 250k forged pieces). Pieces of one input never overlap (parsed so).
    struct OwnedPiece {
        SamplePiece piece;
        size_t image;
    };
    std::vector<OwnedPiece> sorted;
    for (size_t i = 0; i < images.size(); ++i)
        for (const SamplePiece& p : pieces[i]) sorted.push_back({p, i});
    std::sort(sorted.begin(), sorted.end(), [](const OwnedPiece& a, const OwnedPiece& b) {
        if (a.piece.seed != b.piece.seed) return a.piece.seed < b.piece.seed;
        return a.piece.first != b.piece.first ? a.piece.first < b.piece.first : a.image < b.image;
    });
    for (size_t k = 1, furthest = 0; k < sorted.size(); ++k) {
        const OwnedPiece &a = sorted[furthest], &b = sorted[k];
        if (a.piece.seed == b.piece.seed && b.piece.first < a.piece.end) {
            const size_t i = std::min(a.image, b.image), j = std::max(a.image, b.image);
            const int64_t begin = b.piece.first, end = std::min(a.piece.end, b.piece.end);
            throwInputError(nameOf(j), "",
                            "sample indices [" + std::to_string(begin) + ", " + std::to_string(end) +
                                ") overlap with " + nameOf(i) + " (both seed " + std::to_string(a.piece.seed) +
                                "); such partials are not independent, render them with disjoint "
                                "sampler.sample_offset ranges");
        }
        if (a.piece.seed != b.piece.seed || b.piece.end > a.piece.end) furthest = k;
    }
}

Image mergeImages(const std::vector<Image>& images, const std::vector<std::string>& names) {
    auto nameOf = [&](size_t i) { return i < names.size() ? names[i] : "image " + std::to_string(i + 1); };
    checkMergeHeaders(images, names);
    const Image& first = images[0];
    int64_t totalSpp = 0;
    for (const Image& image : images) totalSpp += *image.meta.spp;

    // A render's pixels are radiance estimates: finite and never negative. A partial with
    // NaN, infinity or a negative value is damaged or not a render, and would spread into
    // every merged pixel it touches.
    for (size_t i = 0; i < images.size(); ++i)
        for (size_t k = 0; k < images[i].rgb.size(); ++k)
            if (!(images[i].rgb[k] >= 0.0f && images[i].rgb[k] <= std::numeric_limits<float>::max()))
                throwInputError(nameOf(i), "",
                                "pixel (" + std::to_string(k / 3 % images[i].width) + ", " +
                                    std::to_string(k / 3 / images[i].width) +
                                    ") is NaN, infinite or negative; only renders can be merged");

    Image result;
    result.width = first.width;
    result.height = first.height;
    result.rgb.resize(first.rgb.size());
    for (size_t k = 0; k < result.rgb.size(); ++k) {
        double sum = 0;
        for (const Image& image : images) sum += double(*image.meta.spp) * image.rgb[k];
        result.rgb[k] = float(sum / double(totalSpp));
    }
    result.aovs = mergeAovLayers(images, nameOf);

    ImageMetadata& m = result.meta;
    m.spp = int(totalSpp);
    m.seed = first.meta.seed;
    m.integrator = first.meta.integrator;
    m.sampler = first.meta.sampler;
    bool allKnown = true;
    std::vector<SamplePiece> all;
    for (const Image& image : images) {
        std::vector<SamplePiece> own = samplePiecesOf(image.meta);
        allKnown = allKnown && !own.empty();
        all.insert(all.end(), own.begin(), own.end());
    }
    if (allKnown) m.pieces = normalizeSamplePieces(std::move(all));
    for (const Image& image : images) {
        if (image.meta.sampleOffset) m.sampleOffset = std::min(m.sampleOffset.value_or(INT_MAX), *image.meta.sampleOffset);
        if (image.meta.renderSeconds) m.renderSeconds = m.renderSeconds.value_or(0.0) + *image.meta.renderSeconds;
    }
    return result;
}

}  // namespace penumbra
