// The key table of the preview (see key_bindings.h). GLFW key codes are layout-independent
// positions of a US keyboard, so "1" is the key above Q on every layout.
#include "preview/key_bindings.h"

#include <algorithm>
#include <cctype>
#include <vector>

#include "preview/integrator_controls.h"

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
#define PENUMBRA_KEYS(...) \
    std::vector<int> { __VA_ARGS__ }
#else
#define PENUMBRA_KEYS(...) \
    std::vector<int> {}
#endif

// The GLFW keys of an option key: a digit also on the keypad.
std::vector<int> glfwKeysOf(char key) {
#ifdef PENUMBRA_HAVE_GLFW
    if (key >= '0' && key <= '9') return {GLFW_KEY_0 + (key - '0'), GLFW_KEY_KP_0 + (key - '0')};
    return {GLFW_KEY_A + (key - 'a')};
#else
    (void)key;
    return {};
#endif
}

// "strategy light (direct integrator)", "MIS heuristic: balance <-> power": the option's
// label and the value the key sets, or every value in the order the key steps through them.
std::string optionHelp(const OptionKey& key) {
    const IntegratorOption& option = *key.option;
    std::string help = option.preview.label;
    if (key.value >= 0) {
        help += std::string(" ") + option.values[size_t(key.value)].name;
    } else {
        const char* separator = option.values.size() == 2 ? " <-> " : " -> ";
        help += ": ";
        for (size_t i = 0; i < option.values.size(); ++i)
            help += (i ? separator : "") + std::string(option.values[i].name);
    }
    if (key.value <= 0) help += option.preview.note;  // after the option's first key
    return help;
}

const std::vector<KeyBinding>& bindings() {
    static const std::vector<KeyBinding> table = [] {
        std::vector<KeyBinding> list;
        for (size_t i = 0; i < optionKeys().size(); ++i) {
            const OptionKey& key = optionKeys()[i];
            list.push_back(
                {*optionKeyAction(i), {std::string_view(&key.key, 1)}, glfwKeysOf(key.key), optionHelp(key)});
        }
        std::vector<KeyBinding> others = {
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
        list.insert(list.end(), others.begin(), others.end());
        return list;
    }();
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
