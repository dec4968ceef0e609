// `penumbra merge` and `penumbra compare`: operations on finished EXR renders.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "cli/commands.h"
#include "core/errors.h"
#include "image/image.h"
#include "image/output_check.h"

namespace penumbra {

int mergeCommand(const std::vector<std::string>& inputs, const std::string& output) {
    std::vector<RunFile> readFiles;
    for (const std::string& input : inputs) readFiles.push_back({input, "input"});
    // Bad usage and bad inputs (exit 2) are reported before an unwritable output (exit 1).
    checkDistinctFiles({{output, "-o"}}, readFiles);
    // Every header first: a bad input is refused before any image's pixels take memory.
    std::vector<Image> headers;
    for (const std::string& input : inputs) headers.push_back(readExrHeader(input));
    checkMergeHeaders(headers, inputs);
    headers.clear();
    std::vector<Image> images;
    for (const std::string& input : inputs) images.push_back(readExr(input));
    checkWritable(output);
    writeExr(output, mergeImages(images, inputs));
    return 0;
}

int compareCommand(const std::string& a, const std::string& b) {
    // Sizes from the headers first, so that a mismatch costs no pixels' memory.
    Image headerA = readExrHeader(a), headerB = readExrHeader(b);
    compareImages(headerA, headerB, a, b);
    const Image imageA = readExr(a), imageB = readExr(b);
    // NaN or infinity makes every metric NaN: not a clean comparison that a script could
    // take for a pass (it printed "nan" and exited 0). Refused as bad input, naming the file.
    for (const auto& [image, name] : {std::pair{&imageA, &a}, std::pair{&imageB, &b}}) {
        const size_t bad =
            size_t(std::count_if(image->rgb.begin(), image->rgb.end(), [](float v) { return !std::isfinite(v); }));
        if (bad > 0)
            throwInputError(*name, "",
                            "holds " + std::to_string(bad) + " NaN or infinite values (of " +
                                std::to_string(image->rgb.size()) + "); metrics would be NaN");
    }
    CompareMetrics m = compareImages(imageA, imageB, a, b);
    std::printf("rmse %.9g\nrelmse %.9g\nmean_a %.9g\nmean_b %.9g\nmax_abs %.9g\n", m.rmse, m.relmse, m.meanA, m.meanB,
                m.maxAbs);
    return 0;
}

}  // namespace penumbra
