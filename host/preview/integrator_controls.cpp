// Integrator option keys and the title's integrator label (see integrator_controls.h).
#include "preview/integrator_controls.h"

#include <cstring>

namespace penumbra::preview {

const std::vector<OptionKey>& optionKeys() {
    static const std::vector<OptionKey> keys = [] {
        std::vector<OptionKey> list;
        for (const IntegratorOption& option : integratorOptions()) {
            if (!option.preview.keys) continue;
            const size_t count = std::strlen(option.preview.keys);
            if (count == 1) {
                list.push_back({&option, -1, option.preview.keys[0]});
                continue;
            }
            for (size_t i = 0; i < count; ++i) list.push_back({&option, int(i), option.preview.keys[i]});
        }
        return list;
    }();
    return keys;
}

std::optional<Action> optionKeyAction(size_t index) {
    if (index >= optionKeys().size()) return std::nullopt;
    return Action(uint32_t(Action::FirstOptionKey) + uint32_t(index));
}

const OptionKey* optionKeyOf(Action action) {
    const uint32_t first = uint32_t(Action::FirstOptionKey);
    if (uint32_t(action) < first || uint32_t(action) - first >= optionKeys().size()) return nullptr;
    return &optionKeys()[uint32_t(action) - first];
}

bool isIntegratorAction(Action action) { return optionKeyOf(action) != nullptr; }

bool applyIntegratorAction(IntegratorSettings& settings, Action action) {
    const OptionKey* key = optionKeyOf(action);
    if (!key || settings.type != key->option->integrator) return false;
    const IntegratorOption& option = *key->option;
    const uint32_t now = uint32_t(optionValue(option, settings));
    uint32_t next = 0;
    if (key->value >= 0) {
        next = option.values[size_t(key->value)].value;
        if (next == now) return false;  // already so: no restart
    } else {
        // The value after the current one in table order, the first after the last.
        size_t i = 0;
        while (i < option.values.size() && option.values[i].value != now) ++i;
        next = option.values[(i + 1) % option.values.size()].value;
    }
    option.field.set(settings, next);
    if (option.given) settings.*option.given = true;
    return true;
}

std::string integratorLabel(const IntegratorSettings& settings) {
    if (settings.type == IntegratorType::AmbientOcclusion) return std::string("ao ") + toName(settings.aoSampling);
    std::string label = toName(settings.strategy);
    if (settings.strategy == Strategy::Mis) label += std::string(" ") + toName(settings.heuristic);
    label += std::string(", spheres ") + toName(settings.sphereSampling);
    // The default selection stays unnamed, as in the labels before the light-selection key.
    if (settings.lightSelection != LightSelection::Power)
        label += std::string(", lights ") + toName(settings.lightSelection);
    return label;
}

}  // namespace penumbra::preview
