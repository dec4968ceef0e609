// What the preview reacts to, whether it came from the window (window.cpp) or from an
// input script (input_script.cpp): key actions, mouse drags, the wheel, window resizes.
#pragma once

#include <cstdint>

#include "preview/key_bindings.h"

namespace penumbra::preview {

enum class MouseButton { Left, Right, Middle };

struct InputEvent {
    enum class Type { Key, Drag, Scroll, Resize };
    Type type = Type::Key;
    Action action = Action::Quit;          // Key
    MouseButton button = MouseButton::Left;  // Drag
    double dx = 0.0, dy = 0.0;             // Drag: window pixels (y down); Scroll: wheel steps in dy
    int width = 0, height = 0;             // Resize: window size in screen coordinates

    static InputEvent key(Action a) { return {Type::Key, a}; }
    static InputEvent drag(MouseButton b, double x, double y) { return {Type::Drag, Action::Quit, b, x, y}; }
    static InputEvent scroll(double steps) { return {Type::Scroll, Action::Quit, MouseButton::Left, 0.0, steps}; }
    static InputEvent resize(int w, int h) { return {Type::Resize, Action::Quit, MouseButton::Left, 0.0, 0.0, w, h}; }
};

}  // namespace penumbra::preview
