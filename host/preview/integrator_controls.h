// Live integrator changes in the preview: the strategy, heuristic and sphere, quad and
// triangle sampling keys applied to IntegratorSettings (which EXR saves record through
// scene/integrator_json.h), and the short label the window title shows. Only options of the
// scene's integrator type change: the kernel and the light tables stay as they were built.
#pragma once

#include <string>

#include "preview/key_bindings.h"
#include "scene/scene.h"

namespace penumbra::preview {

// True when `action` changed `settings` (the accumulation must then restart). Actions
// that are not integrator options, and every option key on an ao integrator, change nothing.
bool applyIntegratorAction(IntegratorSettings& settings, Action action);

// Whether `action` is one of the integrator option keys.
bool isIntegratorAction(Action action);

// "mis power, spheres solid_angle", "bsdf, spheres cap", "ao cosine".
std::string integratorLabel(const IntegratorSettings& settings);

}  // namespace penumbra::preview
