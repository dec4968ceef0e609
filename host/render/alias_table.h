// Walker's alias method (Vose's construction, "A Linear Algorithm for Generating Random
// Numbers with a Given Distribution", IEEE TSE 1991): O(1) sampling of a discrete
// distribution on the GPU. Used for light selection and for area-proportional
// triangle selection on mesh lights (lecture: "Mesh Light", p_Delta(i) = A(i) / sum A(k)).
#pragma once

#include <cstdint>
#include <vector>

#include "shared/types.h"

namespace penumbra {

// One entry per weight; entry i carries item[i], its probability pmf = w_i / sum w, and the
// alias *relative to the table's start*. All-zero (or empty-sum) weights give a uniform table.
std::vector<gpu::AliasEntry> buildAliasTable(const std::vector<double>& weights, const std::vector<uint32_t>& items);

// The same table with item i = i, built in `weights`' own storage (left holding Vose's work
// values): for tables of millions of entries (environment maps) one array of doubles and the
// items fewer. The same weights give the same table bit for bit.
std::vector<gpu::AliasEntry> buildAliasTableInPlace(std::vector<double>& weights);

}  // namespace penumbra
