// A primitive beside the tree that no camera ray can hit (see out_of_view.h).
#include "render/out_of_view.h"

#include <array>
#include <cmath>

namespace penumbra {
namespace {

// How far beyond a side of the view pyramid every corner must lie, as a share of its
// distance from the eye: 1e-3 radians, against the kernel's rounding of a direction
// (about 1e-7) and a basis that is orthonormal to about as much.
constexpr double kMargin = 1e-3;

}  // namespace

uint32_t besideOutOfView(const gpu::RenderParams& p, const Bvh& bvh) {
    // A camera ray's direction is forward + x right + y up with |x| <= aspect tan, |y| <= tan
    // (cameraRay), so every point it reaches has dot(n, q - eye) <= 0 for each outward
    // normal n below; a box all of whose corners have dot(n, c - eye) > 0 is missed.
    const glm::dvec3 eye(p.eye), f(p.forward), r(p.right), u(p.up);
    const double t = double(p.tanHalfFovY), a = double(p.aspect) * t;
    const std::array<glm::dvec3, 5> sides = {u - t * f, -u - t * f, r - a * f, -r - a * f, -f};
    for (uint32_t k = 0; k < bvh.besideCount; ++k) {
        glm::vec3 lo, hi;
        primitiveBounds(bvh.primitives[bvh.besideFirst() + k], lo, hi);
        for (const glm::dvec3& n : sides) {
            bool beyond = true;
            for (int c = 0; c < 8 && beyond; ++c) {
                const glm::dvec3 corner(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
                const glm::dvec3 d = corner - eye;
                // Written so that NaN or infinite values fail the test: nothing is left out.
                beyond = glm::dot(n, d) > kMargin * glm::length(n) * glm::length(d);
            }
            if (beyond) return bvh.besideFirst() + k;
        }
    }
    return gpu::NO_HIT;
}

}  // namespace penumbra
