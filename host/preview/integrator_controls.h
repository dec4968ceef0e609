// Live integrator changes in the preview: the keys of the integrator options
// (scene/integrator_options.h, each option's `preview` keys) applied to IntegratorSettings
// (which EXR saves record through scene/integrator_json.h), and the short label the window
// title shows. Only options of the scene's integrator type change: the kernel and the light
// tables stay as they were built.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "preview/key_bindings.h"
#include "scene/scene.h"

namespace penumbra::preview {

// One integrator option key: it sets value `value` of `option`, or steps through the
// option's values (value -1). The key of optionKeys()[i] is Action::FirstOptionKey + i.
struct OptionKey {
    const IntegratorOption* option;
    int value;
    char key;  // its script name, and its key on a US keyboard ("1" also on the keypad)
};

// Every option key, in registry order.
const std::vector<OptionKey>& optionKeys();
// The action of optionKeys()[index]; nothing past the end.
std::optional<Action> optionKeyAction(size_t index);

// True when `action` changed `settings` (the accumulation must then restart). Actions
// that are not integrator options, and every option key on another integrator type's
// options, change nothing.
bool applyIntegratorAction(IntegratorSettings& settings, Action action);

// Whether `action` is one of the integrator option keys.
bool isIntegratorAction(Action action);

// "mis power, spheres solid_angle", "bsdf, spheres cap", "ao cosine".
std::string integratorLabel(const IntegratorSettings& settings);

}  // namespace penumbra::preview
