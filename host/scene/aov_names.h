// The AOV layer names of SCENE_FORMAT.md "AOVs (v3)" (film.aovs and --aov), in the
// contract's order, and the checks of a list of them.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "scene/json_reader.h"

namespace penumbra {

inline constexpr std::array<std::string_view, 8> kAovNames = {"albedo",   "normal",       "position",    "depth",
                                                              "shape_id", "primitive_id", "material_id", "variance"};

// film.aovs: an array of distinct known names. Fails at the element (film.aovs[i]) that
// is no string, no known name, or a repeat.
std::vector<std::string> readAovNames(const JsonReader& list);

}  // namespace penumbra
