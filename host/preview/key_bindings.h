// The preview's keys: one table maps GLFW keys and the names an input script uses to
// actions, and renders the list for `penumbra preview --help` and docs/guide/preview.md.
// What an action does to the camera, integrator or image is the preview loop's business.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace penumbra::preview {

enum class Action : uint32_t {
    ExposureUp,    // +0.5 stop
    ExposureDown,  // -0.5 stop
    CycleLayer,    // rgb -> each of film.aovs -> rgb (preview/layer_cycle.h)
    Save,          // EXR + PNG of the current accumulation
    ResetCamera,
    Quit,
    // The integrator option keys: FirstOptionKey + i is optionKeys()[i]
    // (preview/integrator_controls.h), which the option registry's `preview` keys make. The
    // names below are today's, in registry order (tests/test_preview.cpp checks them); a new
    // option's key needs none.
    FirstOptionKey,
    StrategyLight = FirstOptionKey,
    StrategyBsdf,
    StrategyMis,
    StrategyMixture,
    StrategyRis,
    ToggleHeuristic,         // balance <-> power
    CycleSphereSampling,     // area -> cap -> solid_angle -> area
    ToggleQuadSampling,      // quad lights: area <-> solid_angle
    ToggleTriangleSampling,  // mesh-light triangles: area <-> solid_angle
    CycleLightSelection,     // uniform -> power -> bvh -> uniform (a new Renderer: the light tables)
};

// The action bound to a GLFW key code (GLFW_KEY_*), if any.
std::optional<Action> actionForGlfwKey(int key);
// The action for a key as an input script names it: "1".."5", "h", "s", "t", "m", "l", "+", "-",
// "a", "p", "r", "q", "esc" (case-insensitive).
std::optional<Action> actionForKeyName(std::string_view name);

// The key and mouse list, one binding per line, for --help and docs/guide/preview.md.
std::string keyHelp();

}  // namespace penumbra::preview
