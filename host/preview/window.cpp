// GLFW window, surface and input for the preview (see window.h).
#ifdef PENUMBRA_HAVE_GLFW
#include "preview/window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "gpu/vk_check.h"

namespace penumbra::preview {
namespace {

// The last GLFW error, so that a failure can say why in one line.
std::string g_lastError;
void onGlfwError(int, const char* description) { g_lastError = description ? description : "unknown error"; }

bool environmentSet(const char* name) {
    const char* value = std::getenv(name);
    return value && *value;
}

Window& self(GLFWwindow* window) { return *static_cast<Window*>(glfwGetWindowUserPointer(window)); }

}  // namespace

GlfwSession::GlfwSession() {
    if (!environmentSet("DISPLAY") && !environmentSet("WAYLAND_DISPLAY"))
        throw std::runtime_error(
            "preview needs a display, but DISPLAY and WAYLAND_DISPLAY are unset ('penumbra render' needs none)");
    glfwSetErrorCallback(onGlfwError);
    g_lastError.clear();
    if (glfwInit() != GLFW_TRUE)
        throw std::runtime_error("preview cannot open a window: " +
                                 (g_lastError.empty() ? std::string("glfwInit failed") : g_lastError));
    if (glfwVulkanSupported() != GLFW_TRUE) {
        glfwTerminate();
        throw std::runtime_error("preview cannot open a window: the Vulkan loader offers no surface extensions "
                                 "for this display");
    }
}

GlfwSession::~GlfwSession() { glfwTerminate(); }

std::vector<const char*> GlfwSession::requiredInstanceExtensions() const {
    uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    if (!names) throw std::runtime_error("preview cannot open a window: no Vulkan surface extensions for this display");
    return std::vector<const char*>(names, names + count);
}

VkExtent2D GlfwSession::workArea() const {
    GLFWmonitor* monitor = glfwGetPrimaryMonitor();
    if (!monitor) return {0, 0};
    int x = 0, y = 0, width = 0, height = 0;
    glfwGetMonitorWorkarea(monitor, &x, &y, &width, &height);
    return {uint32_t(std::max(width, 0)), uint32_t(std::max(height, 0))};
}

Window::Window(const std::string& title, int width, int height) {
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    g_lastError.clear();
    m_window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!m_window)
        throw std::runtime_error("preview cannot create a window: " +
                                 (g_lastError.empty() ? std::string("glfwCreateWindow failed") : g_lastError));
    glfwSetWindowUserPointer(m_window, this);
    glfwSetKeyCallback(m_window, onKey);
    glfwSetMouseButtonCallback(m_window, onMouseButton);
    glfwSetCursorPosCallback(m_window, onCursor);
    glfwSetScrollCallback(m_window, onScroll);
    glfwSetWindowRefreshCallback(m_window, onRefresh);
    glfwSetFramebufferSizeCallback(m_window, onFramebufferSize);
    glfwGetCursorPos(m_window, &m_cursor[0], &m_cursor[1]);
}

Window::~Window() {
    if (m_window) glfwDestroyWindow(m_window);
}

VkSurfaceKHR Window::createSurface(VkInstance instance) const {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    gpu::vkCheck(glfwCreateWindowSurface(instance, m_window, nullptr, &surface), "create a Vulkan surface for the window");
    return surface;
}

void Window::pollEvents() { glfwPollEvents(); }
void Window::waitEvents() { glfwWaitEvents(); }

std::vector<InputEvent> Window::takeEvents() {
    std::vector<InputEvent> events;
    events.swap(m_keys);
    for (int b = 0; b < 3; ++b) {
        if (m_drag[b][0] != 0.0 || m_drag[b][1] != 0.0)
            events.push_back(InputEvent::drag(MouseButton(b), m_drag[b][0], m_drag[b][1]));
        m_drag[b][0] = m_drag[b][1] = 0.0;
    }
    if (m_scroll != 0.0) events.push_back(InputEvent::scroll(m_scroll));
    m_scroll = 0.0;
    return events;
}

bool Window::takeRedrawRequest() {
    bool redraw = m_redraw;
    m_redraw = false;
    return redraw;
}

bool Window::shouldClose() const { return glfwWindowShouldClose(m_window) == GLFW_TRUE; }
void Window::requestClose() { glfwSetWindowShouldClose(m_window, GLFW_TRUE); }

VkExtent2D Window::framebufferSize() const {
    int width = 0, height = 0;
    glfwGetFramebufferSize(m_window, &width, &height);
    return {uint32_t(std::max(width, 0)), uint32_t(std::max(height, 0))};
}

VkExtent2D Window::size() const {
    int width = 0, height = 0;
    glfwGetWindowSize(m_window, &width, &height);
    return {uint32_t(std::max(width, 0)), uint32_t(std::max(height, 0))};
}

void Window::setTitle(const std::string& title) { glfwSetWindowTitle(m_window, title.c_str()); }
void Window::setSize(int width, int height) { glfwSetWindowSize(m_window, width, height); }

void Window::onKey(GLFWwindow* window, int key, int, int action, int) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    if (auto bound = actionForGlfwKey(key)) self(window).m_keys.push_back(InputEvent::key(*bound));
}

void Window::onMouseButton(GLFWwindow* window, int button, int action, int) {
    int index = button == GLFW_MOUSE_BUTTON_LEFT    ? int(MouseButton::Left)
                : button == GLFW_MOUSE_BUTTON_RIGHT ? int(MouseButton::Right)
                : button == GLFW_MOUSE_BUTTON_MIDDLE ? int(MouseButton::Middle)
                                                     : -1;
    if (index < 0) return;
    Window& w = self(window);
    w.m_buttonDown[index] = action == GLFW_PRESS;
    glfwGetCursorPos(window, &w.m_cursor[0], &w.m_cursor[1]);
}

void Window::onCursor(GLFWwindow* window, double x, double y) {
    Window& w = self(window);
    for (int b = 0; b < 3; ++b)
        if (w.m_buttonDown[b]) {
            w.m_drag[b][0] += x - w.m_cursor[0];
            w.m_drag[b][1] += y - w.m_cursor[1];
        }
    w.m_cursor[0] = x;
    w.m_cursor[1] = y;
}

void Window::onScroll(GLFWwindow* window, double, double dy) { self(window).m_scroll += dy; }
void Window::onRefresh(GLFWwindow* window) { self(window).m_redraw = true; }
void Window::onFramebufferSize(GLFWwindow* window, int, int) { self(window).m_redraw = true; }

}  // namespace penumbra::preview
#endif  // PENUMBRA_HAVE_GLFW
