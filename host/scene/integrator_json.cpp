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

}  // namespace

nlohmann::json integratorJson(const IntegratorSettings& s) {
    if (s.type == IntegratorType::AmbientOcclusion)
        return {
            {"type", toName(s.type)}, {"sampling", toName(s.aoSampling)}, {"max_distance", decimal(s.aoMaxDistance)}};
    nlohmann::json j = {{"type", toName(s.type)},
                        {"strategy", toName(s.strategy)},
                        {"heuristic", toName(s.heuristic)},
                        {"light_samples", s.lightSamples},
                        {"bsdf_samples", s.bsdfSamples},
                        {"sphere_sampling", toName(s.sphereSampling)},
                        {"light_selection", toName(s.lightSelection)}};
    // Only "ris" reads ris_candidates: other strategies' headers stay as they were.
    if (s.strategy == Strategy::Ris) j["ris_candidates"] = s.risCandidates;
    if (s.quadSamplingGiven) j["quad_sampling"] = toName(s.quadSampling);
    if (s.triangleSamplingGiven) j["triangle_sampling"] = toName(s.triangleSampling);
    return j;
}

}  // namespace penumbra
