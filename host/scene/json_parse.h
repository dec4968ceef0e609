// Parsing JSON input (scene files, job files, --set values, the JSON of glTF models) in
// linear time with the input rules every reader shares: nesting at most kMaxJsonDepth
// levels, checked before any recursive code sees the document, and no duplicate keys.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace penumbra {

// Deep enough for any real scene or model (a scene is 5 levels deep, glTF extras rarely
// 10), shallow enough that recursive code (nlohmann's dump and copies, tinygltf's value
// conversion) stays far from the stack limit.
constexpr size_t kMaxJsonDepth = 256;

// Throws InputError "<label>: line L, column C: nested deeper than 256 levels" when
// arrays and objects nest deeper than kMaxJsonDepth. A linear scan of the bytes (strings
// skipped), so it is safe on any input, valid JSON or not.
void checkJsonDepth(std::string_view text, const std::string& label);

// checkJsonDepth, then a parse that builds the document itself (nlohmann's SAX interface):
// errors are InputError "<label>: line L, column C: syntax error ..." (without echoing the
// text read), "<label>: <json path>: duplicate key \"k\"" and, for a number beyond double
// range, "<label>: <json path>: number is not finite (...)".
nlohmann::json parseJsonText(std::string_view text, const std::string& label);

}  // namespace penumbra
