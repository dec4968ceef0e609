// The integrator object of a scene file, rebuilt from IntegratorSettings' typed fields: the
// value of the EXR header attribute penumbra:integrator, which batch resume compares with
// the job's. Names come from integrator_options.h.
#pragma once

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace penumbra {

// The options of `settings.type` only, every one written out, except quad_sampling and
// triangle_sampling where nothing set them (docs/design/contract-decisions.md), so
// that the header of a scene that does not use them stays as it was before those options.
nlohmann::json integratorJson(const IntegratorSettings& settings);

}  // namespace penumbra
