// Error metrics between two images (penumbra compare): b is the reference. relmse is
// the relative MSE common in adaptive-sampling and denoising papers, (a-b)^2/(b^2+1e-2),
// whose 1e-2 keeps near-black pixels from dominating. Sums are in double.
#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.h"
#include "image/image.h"

namespace penumbra {

CompareMetrics compareImages(const Image& a, const Image& b, const std::string& nameA, const std::string& nameB) {
    if (a.width != b.width || a.height != b.height)
        throwInputError(nameA, "",
                        "size " + std::to_string(a.width) + "x" + std::to_string(a.height) + " differs from " + nameB +
                            " (" + std::to_string(b.width) + "x" + std::to_string(b.height) + ")");
    CompareMetrics m;
    const size_t n = std::min(a.rgb.size(), b.rgb.size());
    if (n == 0) return m;
    double sumSq = 0, sumRel = 0, sumA = 0, sumB = 0;
    for (size_t i = 0; i < n; ++i) {
        const double x = a.rgb[i], y = b.rgb[i], d = x - y;
        sumSq += d * d;
        sumRel += d * d / (y * y + 1e-2);
        sumA += x;
        sumB += y;
        // A NaN difference makes maxAbs NaN (and keeps it so): a broken image must not compare clean.
        if (!std::isnan(m.maxAbs) && !(std::abs(d) <= m.maxAbs)) m.maxAbs = std::abs(d);
    }
    m.rmse = std::sqrt(sumSq / double(n));
    m.relmse = sumRel / double(n);
    m.meanA = sumA / double(n);
    m.meanB = sumB / double(n);
    return m;
}

CompareMetrics compareImages(const Image& a, const Image& b) { return compareImages(a, b, "first image", "second image"); }

}  // namespace penumbra
