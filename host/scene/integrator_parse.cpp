// The integrator object, read option by option from the registry (see integrator_parse.h).
#include "scene/integrator_parse.h"

#include <string>
#include <vector>

namespace penumbra {
namespace {

// "type" and the keys of `type`'s options, in registry order: the order the message lists them.
std::vector<const char*> allowedKeys(IntegratorType type) {
    std::vector<const char*> keys = {"type"};
    for (const IntegratorOption& option : integratorOptions())
        if (option.integrator == type) keys.push_back(option.json);
    return keys;
}

void readOption(const IntegratorOption& option, const JsonReader& r, IntegratorSettings& s) {
    switch (option.kind) {
        case OptionKind::Choice:
            option.field.set(s, valueNamed(option.values, r.choice(allNames(option.values)))->value);
            break;
        case OptionKind::Count: option.field.set(s, double(r.integer(option.min, option.max))); break;
        case OptionKind::Distance: {
            const float distance = r.number();
            if (!(distance > 0.0f)) r.fail("must be > 0");
            option.field.set(s, distance);
            break;
        }
    }
    if (option.given) s.*option.given = true;
}

// The rules across the direct integrator's options.
void checkDirectSamples(const JsonReader& r, const IntegratorSettings& s) {
    // "ris" makes light_samples draws (its BRDF samples are candidates of each draw).
    if (s.strategy == Strategy::Ris && s.lightSamples == 0)
        r.fail("strategy ris makes light_samples draws per sample (raise light_samples)");
    // A strategy with no samples of its own would render only what the camera sees directly.
    bool lightUsed = s.strategy != Strategy::Bsdf, bsdfUsed = s.strategy != Strategy::Light;
    uint32_t used = (lightUsed ? s.lightSamples : 0) + (bsdfUsed ? s.bsdfSamples : 0);
    if (used == 0) r.fail("the strategy takes no samples (raise light_samples or bsdf_samples)");
}

}  // namespace

IntegratorSettings parseIntegrator(const std::optional<JsonReader>& r) {
    IntegratorSettings s;
    if (!r) return s;
    if (r->has("type")) s.type = *fromName<IntegratorType>(r->at("type").choice(allNames<IntegratorType>()));
    r->expectKeys(allowedKeys(s.type), std::string("the ") + toName(s.type) + " integrator");
    for (const IntegratorOption& option : integratorOptions())
        if (option.integrator == s.type)
            if (auto v = r->find(option.json)) readOption(option, *v, s);
    if (s.type == IntegratorType::Direct) checkDirectSamples(*r, s);
    return s;
}

}  // namespace penumbra
