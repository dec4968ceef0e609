// Python values as JSON, for scenes given as dicts and for `set=` values: what json.dumps
// takes (dicts with str keys, lists, tuples, str, int, float, bool, None) and numpy arrays
// and scalars (through their tolist()). Floats keep NaN and infinities, so that the scene's
// validation rejects them at their JSON path as it does in a file ("not finite").
#pragma once

#include <string>

#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>

namespace penumbra::python {

// Throws InputError "<label>: <path>: why" for a value that is not JSON, a dict key that is
// not a str, or nesting deeper than kMaxJsonDepth (scene/json_parse.h), the files' bound.
nlohmann::json jsonFromPython(pybind11::handle value, const std::string& label, const std::string& path = "");

}  // namespace penumbra::python
