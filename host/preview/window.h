// The preview window: GLFW initialised for Vulkan only (no OpenGL context), one window,
// its Vulkan surface, and its input turned into InputEvents (input.h). GLFW is touched
// nowhere else, so `penumbra render` never needs a display.
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "preview/input.h"

struct GLFWwindow;

namespace penumbra::preview {

// glfwInit / glfwTerminate. Throws std::runtime_error with one line saying why there is
// no window to be had: no DISPLAY / WAYLAND_DISPLAY, the display cannot be opened, or the
// Vulkan loader cannot present to windows.
class GlfwSession {
public:
    GlfwSession();
    ~GlfwSession();
    GlfwSession(const GlfwSession&) = delete;
    GlfwSession& operator=(const GlfwSession&) = delete;

    // The instance extensions a surface for a window needs (VK_KHR_surface + the platform's).
    std::vector<const char*> requiredInstanceExtensions() const;
    // The primary monitor's work area in screen coordinates (0 x 0 if unknown).
    VkExtent2D workArea() const;
};

class Window {
public:
    // A window of `width` x `height` screen coordinates. Needs a live GlfwSession.
    Window(const std::string& title, int width, int height);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    // Creates a surface for this window on `instance` (the Context owns and destroys it).
    VkSurfaceKHR createSurface(VkInstance instance) const;

    // Processes pending window-system events without waiting / waiting for at least one.
    void pollEvents();
    void waitEvents();

    // The input gathered since the last call: key actions in order, then at most one
    // drag per button (deltas summed) and one scroll (steps summed).
    std::vector<InputEvent> takeEvents();
    // True once since the last call when the window must be drawn again (exposed, resized).
    bool takeRedrawRequest();

    bool shouldClose() const;
    void requestClose();
    // Framebuffer size in pixels; 0 x 0 while minimised.
    VkExtent2D framebufferSize() const;
    // Window size in screen coordinates, the unit of drag deltas (pixels on most screens).
    VkExtent2D size() const;
    void setTitle(const std::string& title);
    void setSize(int width, int height);

private:
    static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void onMouseButton(GLFWwindow* window, int button, int action, int mods);
    static void onCursor(GLFWwindow* window, double x, double y);
    static void onScroll(GLFWwindow* window, double dx, double dy);
    static void onRefresh(GLFWwindow* window);
    static void onFramebufferSize(GLFWwindow* window, int width, int height);

    GLFWwindow* m_window = nullptr;
    std::vector<InputEvent> m_keys;
    bool m_buttonDown[3] = {false, false, false};  // indexed by MouseButton
    double m_drag[3][2] = {{0, 0}, {0, 0}, {0, 0}};
    double m_cursor[2] = {0, 0};
    double m_scroll = 0.0;
    bool m_redraw = true;
};

}  // namespace penumbra::preview
