// The scene file's `integrator` object (SCENE_FORMAT.md "Integrators") -> IntegratorSettings.
// Which keys each integrator type allows, their kinds, ranges and names come from the option
// registry (integrator_options.h); only the rules that tie several options together live here.
#pragma once

#include <optional>

#include "scene/integrator_options.h"
#include "scene/json_reader.h"

namespace penumbra {

// `integrator` absent: the direct integrator's defaults. Fails (JsonReader::fail: file and
// JSON path) on an unknown key, a value outside its option's values or range, or settings
// that take no samples.
IntegratorSettings parseIntegrator(const std::optional<JsonReader>& integrator);

}  // namespace penumbra
