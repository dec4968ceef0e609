// The BSDF test kernel (shaders/tests/bsdf_sampling.comp) driven from C++, and the chart in
// which the BSDF sampling tests histogram directions: (theta, phi) about the normal, each
// squeezed by a monotone map that spends most cells on a narrow lobe. Shared by
// test_bsdf_sampling.cpp (diffuse, phong) and test_pbr_sampling.cpp (pbr).
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu_fixture.h"
#include "test_frame.h"
#include "tests/bsdf_sampling_test.h"

namespace penumbra::test {

// ---- The kernel -------------------------------------------------------------------------------

class BsdfKernel {
public:
    BsdfKernel()
        : m_ctx(gpuContext()),
          m_kernel(m_ctx, "tests/bsdf_sampling", {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                   sizeof(gpu::BsdfTestPush)) {}

    std::vector<gpu::BsdfTestRecord> run(gpu::BsdfTestPush push, const std::vector<gpu::BsdfTestRecord>& inputs) {
        auto in = inputs.empty() ? gpu::Buffer(m_ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT)
                                 : gpu::Buffer::fromVector(m_ctx, inputs);
        gpu::Buffer out(m_ctx, VkDeviceSize(push.count) * sizeof(gpu::BsdfTestRecord),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
        m_kernel.bind(0, in);
        m_kernel.bind(1, out);
        m_kernel.run((push.count + gpu::BSDF_TEST_WORKGROUP_SIZE - 1) / gpu::BSDF_TEST_WORKGROUP_SIZE, 1, 1, &push);
        auto records = out.read<gpu::BsdfTestRecord>();
        records.resize(push.count);
        return records;
    }

private:
    gpu::Context& m_ctx;
    gpu::Kernel m_kernel;
};

inline BsdfKernel& bsdfKernel() {
    static BsdfKernel kernel;
    return kernel;
}

inline gpu::BsdfTestPush makePush(const gpu::Material& m, glm::vec3 n, glm::vec3 wo, uint32_t mode, uint32_t count,
                                  uint32_t seed) {
    gpu::BsdfTestPush p{};
    p.material = m;
    p.n = n;
    p.wo = wo;
    p.mode = mode;
    p.count = count;
    p.seed = seed;
    return p;
}

// ---- The chart ----------------------------------------------------------------------------------

// Monotone map of [lo, hi] onto [0, 1]: a share `linear` of it linear, the rest an arctangent
// centred on c with width w (dense cells near c). width <= 0 means linear only.
class FocusMap {
public:
    FocusMap(double lo, double hi, double c, double w) : m_lo(lo), m_hi(hi), m_c(c), m_w(w) {
        m_linear = w > 0.0 ? 0.3 : 1.0;
        if (w > 0.0) m_a0 = std::atan((lo - c) / w), m_a1 = std::atan((hi - c) / w);
    }
    double forward(double x) const {
        double f = m_linear * (x - m_lo) / (m_hi - m_lo);
        if (m_linear < 1.0) f += (1.0 - m_linear) * (std::atan((x - m_c) / m_w) - m_a0) / (m_a1 - m_a0);
        return f;
    }
    double derivative(double x) const {
        double d = m_linear / (m_hi - m_lo);
        if (m_linear < 1.0) {
            const double y = (x - m_c) / m_w;
            d += (1.0 - m_linear) / (m_w * (1.0 + y * y) * (m_a1 - m_a0));
        }
        return d;
    }
    double inverse(double f) const {
        // Newton from the linear guess, kept inside a bisection bracket, to ~1e-14.
        double a = m_lo, b = m_hi, x = m_lo + f * (m_hi - m_lo);
        for (int i = 0; i < 100; ++i) {
            const double g = forward(x) - f;
            if (std::abs(g) < 1e-14) break;
            (g < 0.0 ? a : b) = x;
            const double next = x - g / derivative(x);
            x = next > a && next < b ? next : 0.5 * (a + b);
        }
        return x;
    }
    double lo() const { return m_lo; }
    double hi() const { return m_hi; }

private:
    double m_lo, m_hi, m_c, m_w, m_linear = 1.0, m_a0 = 0.0, m_a1 = 0.0;
};

struct Chart {
    Frame frame;
    FocusMap theta, phi;

    glm::dvec2 toChart(glm::dvec3 world) const {
        const glm::dvec3 l = frame.toLocal(world);
        const double th = std::atan2(std::sqrt(l.x * l.x + l.y * l.y), l.z);
        double ph = std::atan2(l.y, l.x);
        while (ph < phi.lo()) ph += 2.0 * std::numbers::pi;
        while (ph >= phi.hi()) ph -= 2.0 * std::numbers::pi;
        return {theta.forward(th), phi.forward(ph)};
    }
    // Direction (world) at chart point st, and d(omega) / (ds dt) there.
    glm::dvec3 fromChart(glm::dvec2 st, double& jacobian) const {
        const double th = theta.inverse(st.x), ph = phi.inverse(st.y);
        jacobian = std::sin(th) / (theta.derivative(th) * phi.derivative(ph));
        return frame.toWorld({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
    }
};

}  // namespace penumbra::test
