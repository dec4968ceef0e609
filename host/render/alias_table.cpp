// Vose's alias table construction (see alias_table.h).
#include "render/alias_table.h"

#include <numeric>

namespace penumbra {

std::vector<gpu::AliasEntry> buildAliasTableInPlace(std::vector<double>& weights) {
    const size_t n = weights.size();
    std::vector<gpu::AliasEntry> table(n);
    if (n == 0) return table;
    double sum = std::accumulate(weights.begin(), weights.end(), 0.0);
    bool uniform = !(sum > 0.0);
    // weights[i] becomes n * p_i once read: 1 means "exactly one slot's worth".
    std::vector<double>& scaled = weights;
    for (size_t i = 0; i < n; ++i) {
        double p = uniform ? 1.0 / double(n) : weights[i] / sum;
        table[i] = {1.0f, uint32_t(i), uint32_t(i), float(p)};
        scaled[i] = p * double(n);
    }
    std::vector<uint32_t> small, large;
    for (size_t i = 0; i < n; ++i) (scaled[i] < 1.0 ? small : large).push_back(uint32_t(i));
    while (!small.empty() && !large.empty()) {
        uint32_t s = small.back(), l = large.back();
        small.pop_back();
        large.pop_back();
        table[s].probability = float(scaled[s]);
        table[s].alias = l;
        scaled[l] -= 1.0 - scaled[s];
        (scaled[l] < 1.0 ? small : large).push_back(l);
    }
    // Left-overs are 1 up to rounding: they keep themselves.
    for (uint32_t i : small) table[i].probability = 1.0f;
    for (uint32_t i : large) table[i].probability = 1.0f;
    return table;
}

std::vector<gpu::AliasEntry> buildAliasTable(const std::vector<double>& weights, const std::vector<uint32_t>& items) {
    std::vector<double> scaled = weights;
    std::vector<gpu::AliasEntry> table = buildAliasTableInPlace(scaled);
    // Aliases are indices into the table; the items only ride along.
    for (size_t i = 0; i < table.size(); ++i) table[i].item = items[i];
    return table;
}

}  // namespace penumbra
