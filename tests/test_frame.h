// The orthonormal frame of common/math.glsl (Duff et al. 2017) in double, for tests that
// move GPU directions into the frame a chi-square histogram is laid out in, and back.
#pragma once

#include <glm/glm.hpp>

namespace penumbra::test {

struct Frame {
    glm::dvec3 t, b, n;

    explicit Frame(glm::dvec3 axis) : n(glm::normalize(axis)) {
        const double s = n.z >= 0.0 ? 1.0 : -1.0;
        const double a = -1.0 / (s + n.z);
        const double c = n.x * n.y * a;
        t = glm::dvec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
        b = glm::dvec3(c, s + n.y * n.y * a, -n.y);
    }
    glm::dvec3 toLocal(glm::dvec3 w) const { return {glm::dot(w, t), glm::dot(w, b), glm::dot(w, n)}; }
    glm::dvec3 toWorld(glm::dvec3 l) const { return l.x * t + l.y * b + l.z * n; }
};

}  // namespace penumbra::test
