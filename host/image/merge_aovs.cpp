// AOV layers of partial renders -> the merged layers (see merge_aovs.h).
#include "image/merge_aovs.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/errors.h"
#include "image/aov_channels.h"

namespace penumbra {

namespace {

std::string namesOf(const Image& image) {
    std::string names;
    for (const AovLayer& layer : image.aovs) names += (names.empty() ? "" : ",") + layer.name;
    return names.empty() ? "none" : names;
}

std::string pixelText(size_t pixel, uint32_t width) {
    return "(" + std::to_string(pixel % width) + ", " + std::to_string(pixel / width) + ")";
}

// Pooled variance of the mean of all N = sum n_i samples from each piece's n_i, mean m_i
// and variance estimate v_i = s_i^2 / n_i (render/aov_layers.cpp). A piece's sum of
// squares is Q_i = (n_i - 1) s_i^2 + n_i m_i^2, so the one render's
//   s^2 = (sum Q_i - N M^2) / (N - 1) = (sum (n_i - 1) n_i v_i + sum n_i (m_i - M)^2) / (N - 1)
// with M = sum n_i m_i / N (the second form has no cancellation); its estimate is s^2 / N
// (Chan, Golub and LeVeque, "Algorithms for computing the sample variance", 1983, eq. 2.1).
// This is the one render's estimate exactly, not sum w_i^2 v_i (w_i = n_i / N): both are
// unbiased, but that one is 0 for pieces of 1 spp (no estimate each) and ignores the spread
// between the pieces' means, which is information about the same variance.
double pooledVariance(const std::vector<double>& n, const std::vector<double>& m, const std::vector<double>& v) {
    double total = 0, weighted = 0;
    for (size_t i = 0; i < n.size(); ++i) {
        total += n[i];
        weighted += n[i] * m[i];
    }
    if (total <= 1) return 0;  // one sample: no estimate, as a render of 1 spp writes
    const double mean = weighted / total;
    double squares = 0;
    for (size_t i = 0; i < n.size(); ++i) squares += (n[i] - 1) * n[i] * v[i] + n[i] * (m[i] - mean) * (m[i] - mean);
    return squares / (total - 1) / total;
}

}  // namespace

void checkMergeAovLists(const std::vector<Image>& images, const std::function<std::string(size_t)>& nameOf) {
    for (size_t i = 1; i < images.size(); ++i) {
        bool same = images[i].aovs.size() == images[0].aovs.size();
        for (size_t k = 0; same && k < images[0].aovs.size(); ++k)
            same = images[i].aovs[k].name == images[0].aovs[k].name;
        if (!same)
            throwInputError(nameOf(i), "",
                            "AOVs " + namesOf(images[i]) + " differ from " + nameOf(0) + "'s (" + namesOf(images[0]) +
                                "); render all partials with the same film.aovs");
    }
}

std::vector<AovLayer> mergeAovLayers(const std::vector<Image>& images,
                                     const std::function<std::string(size_t)>& nameOf) {
    const Image& first = images[0];
    const size_t pixels = size_t(first.width) * first.height;
    std::vector<double> spp;
    for (const Image& image : images) spp.push_back(double(*image.meta.spp));
    auto refuse = [&](size_t i, const AovLayer& layer, size_t pixel, const std::string& why) {
        throwInputError(nameOf(i), "", layer.name + " at pixel " + pixelText(pixel, first.width) + " " + why);
    };

    std::vector<AovLayer> merged;
    for (size_t l = 0; l < first.aovs.size(); ++l) {
        AovLayer out;
        out.name = first.aovs[l].name;
        out.channels = first.aovs[l].channels;
        if (aovHoldsIds(out.name)) {
            out.ids = first.aovs[l].ids;
            for (size_t i = 1; i < images.size(); ++i)
                for (size_t p = 0; p < pixels; ++p)
                    if (images[i].aovs[l].ids[p] != out.ids[p])
                        refuse(i, images[i].aovs[l], p,
                               "is " + std::to_string(images[i].aovs[l].ids[p]) + " but " + std::to_string(out.ids[p]) +
                                   " in " + nameOf(0) + "; partials of one scene have the same ids");
            merged.push_back(std::move(out));
            continue;
        }
        const size_t n = out.channels.size();
        out.floats.assign(pixels * n, 0.0f);
        const bool depth = out.name == "depth", variance = out.name == "variance";
        std::vector<double> counts(images.size()), means(images.size()), variances(images.size());
        for (size_t k = 0; k < pixels * n; ++k) {
            double sum = 0, weight = 0;
            for (size_t i = 0; i < images.size(); ++i) {
                const float v = images[i].aovs[l].floats[k];
                const bool finite = std::isfinite(v);
                // Depth is +inf where no sample hit; no other AOV value is ever infinite.
                if (!(finite || (depth && v == std::numeric_limits<float>::infinity())))
                    refuse(i, images[i].aovs[l], k / n, "is NaN or infinite; only renders can be merged");
                if ((depth || variance) && v < 0)
                    refuse(i, images[i].aovs[l], k / n, "is negative; only renders can be merged");
                if (variance) {
                    counts[i] = spp[i];
                    means[i] = images[i].rgb[k];  // variance.R/G/B pair with R, G, B
                    variances[i] = v;
                } else if (finite) {
                    sum += spp[i] * v;
                    weight += spp[i];
                }
            }
            out.floats[k] = variance     ? float(pooledVariance(counts, means, variances))
                            : weight > 0 ? float(sum / weight)
                                         : std::numeric_limits<float>::infinity();  // depth: no piece hit
        }
        merged.push_back(std::move(out));
    }
    return merged;
}

}  // namespace penumbra
