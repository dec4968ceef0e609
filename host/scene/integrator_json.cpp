// IntegratorSettings -> the integrator object of the EXR header (see integrator_json.h).
#include "scene/integrator_json.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>

#include "scene/integrator_options.h"

namespace penumbra {
namespace {

// A float option as the scene file most likely wrote it: the shortest decimal that reads
// back as the same float (0.1f is 0.1, not 0.10000000149011612), and an integer when that
// is integral, as a hand-written `"max_distance": 5` is.
nlohmann::json decimal(float value) {
    char text[32];
    const char* end = std::to_chars(text, text + sizeof(text), value).ptr;
    double shortest = 0.0;
    std::from_chars(text, end, shortest);  // locale-independent, like to_chars
    if (std::fabs(shortest) < 9007199254740992.0 && shortest == std::trunc(shortest)) return int64_t(shortest);
    return shortest;
}

// An option's value as the scene file writes it: a choice by name, a count as an integer.
nlohmann::json headerValue(const IntegratorOption& option, const IntegratorSettings& s) {
    const double value = optionValue(option, s);
    switch (option.kind) {
        case OptionKind::Choice: {
            const OptionValue* entry = valueNumbered(option.values, uint32_t(value));
            return entry ? entry->name : "?";  // "?" only for a value outside its enum, as toName
        }
        case OptionKind::Count: return uint32_t(value);
        case OptionKind::Distance: return decimal(float(value));
    }
    return nullptr;
}

}  // namespace

nlohmann::json integratorJson(const IntegratorSettings& s) {
    nlohmann::json j = nlohmann::json::object();
    j["type"] = toName(s.type);
    for (const IntegratorOption& option : integratorOptions()) {
        // Options not in effect (ris_candidates under another strategy) and options that
        // list themselves only when given stay out, so those headers stay as they were.
        if (!optionInEffect(option, s) || (option.given && !(s.*option.given))) continue;
        j[option.json] = headerValue(option, s);
    }
    return j;
}

}  // namespace penumbra
