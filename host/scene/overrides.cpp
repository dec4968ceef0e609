// `--set PATH=VALUE`: parsing the option and applying it to a scene document before it is
// validated (so an override is checked exactly like a value written in the file).
// Validation of the result is load_json.cpp's.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <variant>

#include "core/errors.h"
#include "scene/json_parse.h"
#include "scene/json_reader.h"
#include "scene/load.h"

namespace penumbra {
namespace {

using Step = std::variant<std::string, size_t>;  // object key or array index

[[noreturn]] void failOverride(const Override& o, const std::string& why) {
    throw InputError("--set " + o.path + "=" + o.value + ": " + why);
}

[[noreturn]] void failMalformed(const Override& o, const std::string& why) {
    failOverride(o, why + " (expected --set PATH=VALUE with PATH like integrator.strategy or lights[0].power)");
}

// "lights[0].power" -> "lights", 0, "power". Keys are non-empty and contain none of ".[]=".
std::vector<Step> splitPath(const Override& o) {
    const std::string& p = o.path;
    std::vector<Step> steps;
    size_t i = 0;
    while (true) {
        size_t start = i;
        while (i < p.size() && p[i] != '.' && p[i] != '[' && p[i] != ']') ++i;
        if (i == start) failMalformed(o, "empty key in path \"" + p + "\"");
        steps.emplace_back(p.substr(start, i - start));
        while (i < p.size() && p[i] == '[') {
            size_t close = p.find(']', i);
            std::string digits = p.substr(i + 1, close == std::string::npos ? std::string::npos : close - i - 1);
            bool ok = close != std::string::npos && !digits.empty() && digits.size() <= 9 &&
                      std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); });
            if (!ok) failMalformed(o, "bad array index in path \"" + p + "\"");
            steps.emplace_back(size_t(std::stoul(digits)));
            i = close + 1;
        }
        if (i == p.size()) return steps;
        if (p[i] != '.') failMalformed(o, "unexpected '" + std::string(1, p[i]) + "' in path \"" + p + "\"");
        ++i;
    }
}

}  // namespace

Override parseOverride(const std::string& text) {
    size_t eq = text.find('=');
    if (eq == std::string::npos)
        throw InputError("--set " + text + ": missing '=' (expected --set PATH=VALUE, e.g. sampler.spp=16)");
    Override o{text.substr(0, eq), text.substr(eq + 1)};
    splitPath(o);  // reject a malformed path now, before any file is read
    return o;
}

void applyOverride(nlohmann::json& doc, const Override& o) {
    // The value is JSON if it parses as JSON (numbers, arrays, true, "quoted"), else a string,
    // so `integrator.strategy=bsdf` needs no shell-quoted JSON string.
    // The shared rules hold here too: the depth is checked before parsing, and a value
    // that is JSON is parsed again by parseJsonText to refuse duplicate keys.
    const std::string label = "--set " + o.path;
    checkJsonDepth(o.value, label);
    nlohmann::json value = nlohmann::json::parse(o.value, nullptr, /*allow_exceptions=*/false);
    if (value.is_discarded()) value = o.value;
    else value = parseJsonText(o.value, label);
    // A JSON number beyond double range (1e999) fails to parse; keep it a number (+-inf) so
    // that validation reports "not finite" at its path rather than "expected a number".
    bool numeric = !o.value.empty() && (std::isdigit((unsigned char)o.value[0]) ||
                                        (o.value.size() > 1 && o.value[0] == '-' && std::isdigit((unsigned char)o.value[1])));
    char* end = nullptr;
    double number = numeric && value.is_string() ? std::strtod(o.value.c_str(), &end) : 0.0;
    if (end && *end == '\0' && std::isinf(number)) value = number;
    applyOverrideValue(doc, o, std::move(value));
}

void applyOverrideValue(nlohmann::json& doc, const Override& o, nlohmann::json value) {
    nlohmann::json* node = &doc;
    std::string where;  // the path walked so far, for messages
    for (const Step& step : splitPath(o)) {
        if (const std::string* key = std::get_if<std::string>(&step)) {
            if (node->is_null()) *node = nlohmann::json::object();
            if (!node->is_object())
                failOverride(o, (where.empty() ? "the document" : where) + " is not an object");
            node = &(*node)[*key];
            where = joinPath(where, *key);
        } else {
            size_t index = std::get<size_t>(step);
            if (node->is_null()) *node = nlohmann::json::array();
            if (!node->is_array()) failOverride(o, where + " is not an array");
            if (index > node->size())
                failOverride(o, "index " + std::to_string(index) + " out of range (" + where + " has " +
                                    std::to_string(node->size()) + " elements; " + std::to_string(node->size()) +
                                    " appends)");
            if (index == node->size()) node->push_back(nullptr);
            node = &(*node)[index];
            where = indexPath(where, index);
        }
    }
    *node = std::move(value);
}

}  // namespace penumbra
