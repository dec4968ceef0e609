// `penumbra merge` and `penumbra compare`: operations on finished EXR renders.
#include <cstdio>

#include "cli/commands.h"
#include "image/image.h"

namespace penumbra {

int mergeCommand(const std::vector<std::string>& inputs, const std::string& output) {
    std::vector<Image> images;
    for (const std::string& input : inputs) images.push_back(readExr(input));
    writeExr(output, mergeImages(images, inputs));
    return 0;
}

int compareCommand(const std::string& a, const std::string& b) {
    CompareMetrics m = compareImages(readExr(a), readExr(b), a, b);
    std::printf("rmse %.9g\nrelmse %.9g\nmean_a %.9g\nmean_b %.9g\nmax_abs %.9g\n", m.rmse, m.relmse, m.meanA, m.meanB,
                m.maxAbs);
    return 0;
}

}  // namespace penumbra
