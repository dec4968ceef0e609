// The key table of the preview (see key_bindings.h). GLFW key codes are layout-independent
// positions of a US keyboard, so "1" is the key above Q on every layout.
#include "preview/key_bindings.h"

#include <algorithm>
#include <cctype>
#include <vector>

#include "scene/integrator_options.h"

#ifdef PENUMBRA_HAVE_GLFW
#include <GLFW/glfw3.h>
#endif

namespace penumbra::preview {
namespace {

struct KeyBinding {
    Action action;
    std::vector<std::string_view> names;  // script names; the first is shown in help
    std::vector<int> glfwKeys;
    std::string help;
};

#ifdef PENUMBRA_HAVE_GLFW
#define PENUMBRA_KEYS(...) std::vector<int>{__VA_ARGS__}
#else
#define PENUMBRA_KEYS(...) \
    std::vector<int> {}
#endif

// The names of E's values in the order the preview steps through them (nextValue).
template <class E>
std::string valueCycle(const char* separator) {
    std::string text;
    for (const OptionValue& entry : enumNames(E{})) text += (text.empty() ? "" : separator) + std::string(entry.name);
    return text;
}

std::string strategyHelp(Strategy strategy) { return std::string("strategy ") + toName(strategy); }

const std::vector<KeyBinding>& bindings() {
    static const std::vector<KeyBinding> table = {
        {Action::StrategyLight,
         {"1"},
         PENUMBRA_KEYS(GLFW_KEY_1, GLFW_KEY_KP_1),
         strategyHelp(Strategy::Light) + " (direct integrator)"},
        {Action::StrategyBsdf, {"2"}, PENUMBRA_KEYS(GLFW_KEY_2, GLFW_KEY_KP_2), strategyHelp(Strategy::Bsdf)},
        {Action::StrategyMis, {"3"}, PENUMBRA_KEYS(GLFW_KEY_3, GLFW_KEY_KP_3), strategyHelp(Strategy::Mis)},
        {Action::StrategyMixture, {"4"}, PENUMBRA_KEYS(GLFW_KEY_4, GLFW_KEY_KP_4), strategyHelp(Strategy::Mixture)},
        {Action::StrategyRis, {"5"}, PENUMBRA_KEYS(GLFW_KEY_5, GLFW_KEY_KP_5), strategyHelp(Strategy::Ris)},
        {Action::ToggleHeuristic, {"h"}, PENUMBRA_KEYS(GLFW_KEY_H), "MIS heuristic: " + valueCycle<Heuristic>(" <-> ")},
        {Action::CycleSphereSampling,
         {"s"},
         PENUMBRA_KEYS(GLFW_KEY_S),
         "sphere sampling: " + valueCycle<SphereSampling>(" -> ")},
        {Action::ToggleQuadSampling,
         {"t"},
         PENUMBRA_KEYS(GLFW_KEY_T),
         "quad sampling: " + valueCycle<QuadSampling>(" <-> ")},
        {Action::ToggleTriangleSampling,
         {"m"},
         PENUMBRA_KEYS(GLFW_KEY_M),
         "mesh-light triangle sampling: " + valueCycle<TriangleSampling>(" <-> ")},
        {Action::CycleLightSelection,
         {"l"},
         PENUMBRA_KEYS(GLFW_KEY_L),
         "light selection: " + valueCycle<LightSelection>(" -> ") + " (rebuilds the light tables)"},
        {Action::ExposureUp, {"+", "plus"}, PENUMBRA_KEYS(GLFW_KEY_EQUAL, GLFW_KEY_KP_ADD), "exposure +0.5 stop"},
        {Action::ExposureDown,
         {"-", "minus"},
         PENUMBRA_KEYS(GLFW_KEY_MINUS, GLFW_KEY_KP_SUBTRACT),
         "exposure -0.5 stop"},
        {Action::CycleLayer,
         {"a"},
         PENUMBRA_KEYS(GLFW_KEY_A),
         "shown layer: rgb -> each of film.aovs -> rgb (scenes with AOVs)"},
        {Action::Save,
         {"p"},
         PENUMBRA_KEYS(GLFW_KEY_P),
         "save SCENE-preview-N.exr and .png of the current accumulation"},
        {Action::ResetCamera, {"r"}, PENUMBRA_KEYS(GLFW_KEY_R), "reset the camera to the scene's"},
        {Action::Quit, {"q", "esc"}, PENUMBRA_KEYS(GLFW_KEY_Q, GLFW_KEY_ESCAPE), "quit"},
    };
    return table;
}

std::string lower(std::string_view text) {
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return out;
}

}  // namespace

std::optional<Action> actionForGlfwKey(int key) {
    for (const KeyBinding& binding : bindings())
        if (std::find(binding.glfwKeys.begin(), binding.glfwKeys.end(), key) != binding.glfwKeys.end())
            return binding.action;
    return std::nullopt;
}

std::optional<Action> actionForKeyName(std::string_view name) {
    std::string wanted = lower(name);
    for (const KeyBinding& binding : bindings())
        for (std::string_view candidate : binding.names)
            if (candidate == wanted) return binding.action;
    return std::nullopt;
}

std::string keyHelp() {
    std::string text;
    auto line = [&text](std::string keys, std::string_view help) {
        keys.resize(std::max<size_t>(keys.size() + 2, 20), ' ');
        text += "  " + keys + std::string(help) + "\n";
    };
    line("left drag", "orbit the camera around its target");
    line("right/middle drag", "pan");
    line("wheel", "zoom (towards / away from the target)");
    for (const KeyBinding& binding : bindings()) {
        std::string keys = binding.action == Action::Quit ? "Q, Esc" : std::string(binding.names[0]);
        if (keys.size() == 1) keys[0] = char(std::toupper(static_cast<unsigned char>(keys[0])));
        line(keys, binding.help);
    }
    text += "Every camera or integrator change restarts the accumulation.";
    return text;
}

}  // namespace penumbra::preview
