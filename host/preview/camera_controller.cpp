// Orbit, pan and zoom of the preview camera (see camera_controller.h).
#include "preview/camera_controller.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>

namespace penumbra::preview {
namespace {

// Smallest angle kept between the view direction and the up axis, radians.
constexpr double kPoleMargin = 1e-3;

}  // namespace

CameraController::CameraController(const Camera& initial) : m_initial(initial), m_camera(initial) {}

void CameraController::orbit(double dx, double dy, double viewHeight) {
    if (viewHeight <= 0.0 || (dx == 0.0 && dy == 0.0)) return;
    const glm::dvec3 up = glm::normalize(glm::dvec3(m_camera.up));
    const glm::dvec3 target(m_camera.target);
    const glm::dvec3 offset = glm::dvec3(m_camera.eye) - target;
    const double radius = glm::length(offset);
    if (radius <= 0.0) return;
    // Spherical coordinates of the eye about the target: polar angle from `up`, azimuth
    // in the plane orthogonal to it (basis e1, e2 with e1 x e2 = up).
    glm::dvec3 e1 = offset - glm::dot(offset, up) * up;
    if (glm::length(e1) < 1e-12 * radius) e1 = std::abs(up.x) < 0.9 ? glm::cross(up, glm::dvec3(1, 0, 0))
                                                                      : glm::cross(up, glm::dvec3(0, 1, 0));
    e1 = glm::normalize(e1);
    const glm::dvec3 e2 = glm::cross(up, e1);
    double polar = std::acos(std::clamp(glm::dot(offset, up) / radius, -1.0, 1.0));
    double azimuth = 0.0;  // measured from e1, the eye's current direction

    const double radiansPerPixel = glm::pi<double>() / viewHeight;
    // Dragging right turns the scene right (the eye moves left around the target);
    // dragging down shows it from above.
    azimuth -= dx * radiansPerPixel;
    polar = std::clamp(polar - dy * radiansPerPixel, kPoleMargin, glm::pi<double>() - kPoleMargin);
    glm::dvec3 dir = std::sin(polar) * (std::cos(azimuth) * e1 + std::sin(azimuth) * e2) + std::cos(polar) * up;
    m_camera.eye = glm::vec3(target + radius * dir);
}

void CameraController::pan(double dx, double dy, double viewHeight) {
    if (viewHeight <= 0.0 || (dx == 0.0 && dy == 0.0)) return;
    const glm::dvec3 eye(m_camera.eye), target(m_camera.target);
    const glm::dvec3 forward = glm::normalize(target - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(m_camera.up)));
    const glm::dvec3 up = glm::cross(right, forward);
    // World units per pixel at the target's depth (the film spans 2 tan(fov/2) * distance).
    const double scale = 2.0 * glm::length(target - eye) * std::tan(0.5 * glm::radians(double(m_camera.fovY))) /
                         viewHeight;
    const glm::dvec3 shift = (-dx * right + dy * up) * scale;
    m_camera.eye = glm::vec3(eye + shift);
    m_camera.target = glm::vec3(target + shift);
}

void CameraController::zoom(double steps) {
    if (steps == 0.0) return;
    const glm::dvec3 eye(m_camera.eye), target(m_camera.target);
    const double distance = glm::length(eye - target);
    const double initial = glm::length(glm::dvec3(m_initial.eye) - glm::dvec3(m_initial.target));
    double next = distance * std::pow(0.9, steps);
    next = std::clamp(next, 1e-4 * initial, 1e4 * initial);
    m_camera.eye = glm::vec3(target + (eye - target) * (next / distance));
}

}  // namespace penumbra::preview
