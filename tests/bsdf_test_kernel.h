// The BSDF test kernel (shaders/tests/bsdf_sampling.comp) driven from C++, the chart in
// which the BSDF sampling tests histogram directions: (theta, phi) about the normal, each
// squeezed by a monotone map that spends most cells on a narrow lobe, and the chi-square
// test's inputs in that chart. Shared by test_bsdf_sampling.cpp (diffuse, phong) and
// test_pbr_sampling.cpp (pbr).
#pragma once

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <glm/glm.hpp>

#include "chi2.h"
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

// The chart about the mirror direction of wo at n, for a lobe of angular radius `width`
// (radians) about it: focused on the lobe when it is narrower than ~30 degrees (0.5 rad),
// linear otherwise.
inline Chart mirrorChart(glm::vec3 wo, glm::vec3 n, double width) {
    constexpr double kPi = std::numbers::pi;
    const Frame frame{glm::dvec3(n)};
    const glm::dvec3 r = frame.toLocal(2.0 * glm::dot(glm::dvec3(wo), glm::dvec3(n)) * glm::dvec3(n) - glm::dvec3(wo));
    const double thetaC = std::atan2(std::sqrt(r.x * r.x + r.y * r.y), r.z);
    const double phiC = std::atan2(r.y, r.x);
    const double wTheta = width < 0.5 ? width : 0.0;
    const double wPhi = width < 0.5 && std::sin(thetaC) > width ? width / std::sin(thetaC) : 0.0;
    return {frame, FocusMap(0.0, 0.5 * kPi, thetaC, wTheta), FocusMap(phiC - kPi, phiC + kPi, phiC, wPhi)};
}

// ---- The chi-square test in the chart ------------------------------------------------------------

// bsdfSample's directions (the kernel's SAMPLE records) as chart points for chi2TestSquare;
// a declined sample (an all-zero record) becomes NaN, the harness's mark for "no sample".
inline std::vector<glm::dvec2> chartPoints(const Chart& chart, const std::vector<gpu::BsdfTestRecord>& samples) {
    std::vector<glm::dvec2> points(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
        const auto& s = samples[i];
        if (s.a == glm::vec4(0.0f)) {
            points[i] = {std::numeric_limits<double>::quiet_NaN(), 0.0};
            continue;
        }
        // A direction the GPU put just above the horizon can land a rounding (1e-7
        // radian, times F' <= 25 here) past s = 1 in double: keep it in the chart.
        glm::dvec2 st = chart.toChart(glm::normalize(glm::dvec3(glm::vec3(s.a))));
        if (st.x > 1.0 && st.x < 1.0 + 1e-5) st.x = 1.0;
        points[i] = st;
    }
    return points;
}

// The kernel's bsdfPdf as a density in the chart, w.r.t. ds dt: the solid-angle pdf times
// d(omega) / (ds dt), as chi2TestSquare wants it.
inline SquarePdf chartPdf(BsdfKernel& kernel, const gpu::Material& m, glm::vec3 n, glm::vec3 wo, const Chart& chart) {
    return [&kernel, m, n, wo, chart](const std::vector<glm::dvec2>& st) {
        std::vector<gpu::BsdfTestRecord> in(st.size());
        std::vector<double> jac(st.size());
        for (size_t i = 0; i < st.size(); ++i) in[i].a = glm::vec4(glm::vec3(chart.fromChart(st[i], jac[i])), 0.0f);
        const auto out = kernel.run(makePush(m, n, wo, gpu::BSDF_TEST_MODE_PDF, uint32_t(st.size()), 0), in);
        std::vector<double> values(st.size());
        for (size_t i = 0; i < st.size(); ++i) values[i] = double(out[i].a.x) * jac[i];
        return values;
    };
}

}  // namespace penumbra::test
