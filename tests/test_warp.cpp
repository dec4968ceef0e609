// The warps of shaders/sampling/warp.glsl, drawn on the GPU (lavapipe): each warp's
// samples pass a chi-square test against its own GLSL pdf (tests/chi2.h), the pdf
// integrates to 1, every sample has a positive pdf that agrees with a closed form on the
// host, and the harness itself rejects deliberately wrong pdfs.
//
// Significance: alpha = 0.01 for the whole file, Sidak-corrected over kChi2Tests tests.
// Seeds are fixed, so a pass or a failure is reproducible.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "chi2.h"
#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu_fixture.h"
#include "tests/warp_test.h"

using namespace penumbra;
using gpu::WarpPush;

namespace {

constexpr double kAlpha = 0.01;
// Chi-square tests in this file that must pass: 2 hemispheres + 6 Phong exponents +
// 1 sphere + 5 cones + disk + triangle.
constexpr int kChi2Tests = 16;
constexpr uint32_t kSamples = 1u << 20;  // >= 10^6 per warp
constexpr double kPi = std::numbers::pi;

// The warp test kernel (shaders/tests/warp.comp), created once: lavapipe compiles the
// pipeline on its first dispatch, which should not be paid per test.
class WarpKernel {
public:
    WarpKernel()
        : m_ctx(test::gpuContext()),
          m_kernel(m_ctx, "tests/warp", {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                   sizeof(WarpPush)) {}

    // kSamples samples of `warp`: (sample, pdf at the sample), see tests/warp_test.h.
    std::vector<glm::vec4> sample(uint32_t warp, float param, uint32_t seed, uint32_t count = kSamples) {
        gpu::Buffer unused(m_ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
        gpu::Buffer out(m_ctx, VkDeviceSize(count) * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
        WarpPush push{gpu::WARP_MODE_SAMPLE, warp, count, seed, param, 0, 0, 0};
        dispatch(unused, out, push);
        return out.read<glm::vec4>();
    }

    // The GLSL pdf of `warp` at each point (xyz used).
    std::vector<double> pdf(uint32_t warp, float param, const std::vector<glm::vec4>& points) {
        auto in = gpu::Buffer::fromVector(m_ctx, points);
        gpu::Buffer out(m_ctx, VkDeviceSize(points.size()) * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
        WarpPush push{gpu::WARP_MODE_PDF, warp, uint32_t(points.size()), 0, param, 0, 0, 0};
        dispatch(in, out, push);
        auto values = out.read<glm::vec4>();
        std::vector<double> result(points.size());
        for (size_t i = 0; i < points.size(); ++i) result[i] = values[i].x;
        return result;
    }

    test::DirectionPdf directionPdf(uint32_t warp, float param, double scale = 1.0) {
        return [this, warp, param, scale](const std::vector<glm::vec3>& dirs) {
            std::vector<glm::vec4> points(dirs.size());
            for (size_t i = 0; i < dirs.size(); ++i) points[i] = glm::vec4(dirs[i], 0.0f);
            auto values = pdf(warp, param, points);
            for (double& v : values) v *= scale;
            return values;
        };
    }

private:
    void dispatch(const gpu::Buffer& in, const gpu::Buffer& out, const WarpPush& push) {
        m_kernel.bind(0, in);
        m_kernel.bind(1, out);
        m_kernel.run((push.count + gpu::WARP_WORKGROUP_SIZE - 1) / gpu::WARP_WORKGROUP_SIZE, 1, 1, &push);
    }

    gpu::Context& m_ctx;
    gpu::Kernel m_kernel;
};

WarpKernel& warpKernel() {
    static WarpKernel kernel;
    return kernel;
}

std::vector<glm::vec3> directionsOf(const std::vector<glm::vec4>& samples) {
    std::vector<glm::vec3> dirs(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) dirs[i] = glm::vec3(samples[i]);
    return dirs;
}

// One direction warp under test: its id and parameter, the cap the chi2 histogram zooms
// on (see SphereChi2Options), and the pdf in closed form (double, host) for comparison.
struct DirectionCase {
    std::string name;
    uint32_t warp;
    float param;
    double cap;
    std::function<double(glm::dvec3)> referencePdf;
    // GLSL pdf at the sample vs referencePdf: |difference| <= pdfTolerance * reference +
    // pdfAbsTolerance (the absolute part covers tiny densities near a lobe's horizon, where
    // the float rounding of z, ~6e-8, is a large fraction of cos).
    double pdfTolerance = 1e-5;
    double pdfAbsTolerance = 0.0;
};

// Draws the samples and checks everything a direction warp promises.
void checkDirectionWarp(const DirectionCase& c, uint32_t seed) {
    auto& k = warpKernel();
    const auto samples = k.sample(c.warp, c.param, seed);
    ASSERT_EQ(samples.size(), kSamples);

    // Each sample: finite, unit length, pdf > 0 (so it lies in the support), and the GLSL
    // pdf agrees with the closed form in double, within float32 exp/log on the GPU and, for
    // cos^n, the float spacing of cos (~6e-8) amplified by n. The one exception: a sample
    // exactly on the rim z = 0 of the cosine hemisphere (u.x or u.y = 0 gives radius 1, chance
    // ~2^-23) has pdf 0 there, as in pbrt and Nori; the closed form must then agree.
    size_t bad = 0;
    for (size_t i = 0; i < samples.size() && bad < 5; ++i) {
        const glm::vec4 s = samples[i];
        const glm::dvec3 d(s.x, s.y, s.z);
        const double ref = c.referencePdf(d);
        const bool onRim = d.z == 0.0 && s.w == 0.0f && ref == 0.0 && c.warp == gpu::WARP_COSINE_HEMISPHERE;
        const bool ok = std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.z) && std::isfinite(s.w) &&
                        std::abs(glm::dot(d, d) - 1.0) < 1e-5 &&
                        (onRim || (s.w > 0.0f && ref > 0.0 &&
                                   std::abs(s.w - ref) <= c.pdfTolerance * ref + c.pdfAbsTolerance));
        if (!ok) {
            ++bad;
            ADD_FAILURE() << c.name << ": sample " << i << " = (" << s.x << ", " << s.y << ", " << s.z
                          << ") has pdf " << s.w << ", closed form " << ref;
        }
    }
    ASSERT_EQ(bad, 0u);

    test::SphereChi2Options options;
    options.capOneMinusCos = c.cap;
    options.significance = kAlpha;
    options.numTests = kChi2Tests;
    options.dumpName = "chi2_" + c.name;
    const auto r = test::chi2TestSphere(directionsOf(samples), k.directionPdf(c.warp, c.param), options);
    EXPECT_TRUE(r.passed) << c.name << ": " << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, r.integralTolerance) << c.name << ": " << r.message;
    std::printf("[ %s ] %s\n", c.name.c_str(), r.message.c_str());
}

double hemisphere(glm::dvec3 d, double value) { return d.z >= 0.0 ? value : 0.0; }

// 1 - cos(theta) without cancellation near the pole (as oneMinusCosTheta in warp.glsl).
double oneMinusCos(glm::dvec3 d) { return d.z > 0.0 ? (d.x * d.x + d.y * d.y) / (1.0 + d.z) : 1.0 - d.z; }

// (n+1)/(2 pi) cos^n. Near the pole cos^n comes from the sample's accurate 1 - cos rather
// than its z, whose float rounding n would amplify (the GPU pdf sees the unrounded cos).
double phongReference(glm::dvec3 d, double n) {
    if (d.z <= 0.0) return 0.0;
    const double cosN = d.z < 0.5 ? std::pow(d.z, n) : std::exp(n * std::log1p(-oneMinusCos(d)));
    return (n + 1.0) / (2.0 * kPi) * cosN;
}

DirectionCase coneCase(const std::string& name, uint32_t warp, float param, double oneMinusCosMax) {
    return {name, warp, param, oneMinusCosMax, [oneMinusCosMax](glm::dvec3 d) {
                return oneMinusCos(d) <= oneMinusCosMax * (1.0 + 1e-5) ? 1.0 / (2.0 * kPi * oneMinusCosMax) : 0.0;
            }};
}

}  // namespace

// ---- Direction warps ---------------------------------------------------------------------

TEST(Warp, UniformHemisphere) {
    checkDirectionWarp({"uniform_hemisphere", gpu::WARP_UNIFORM_HEMISPHERE, 0.0f, 1.0,
                        [](glm::dvec3 d) { return hemisphere(d, 1.0 / (2.0 * kPi)); }},
                       1);
}

TEST(Warp, CosineHemisphere) {
    checkDirectionWarp({"cosine_hemisphere", gpu::WARP_COSINE_HEMISPHERE, 0.0f, 1.0,
                        [](glm::dvec3 d) { return d.z > 0.0 ? d.z / kPi : 0.0; }},
                       2);
}

TEST(Warp, PhongLobe) {
    // The cap holds all but (1 - cap)^(n+1) ~ e^-8 of the lobe's mass, so the rows resolve
    // the lobe even at n = 10^4, where it is ~10^-4 wide in 1 - cos.
    uint32_t seed = 3;
    for (double n : {0.0, 1.0, 10.0, 100.0, 1000.0, 10000.0}) {
        SCOPED_TRACE("n = " + std::to_string(n));
        const double cap = std::min(1.0, 8.0 / (n + 1.0));
        checkDirectionWarp({"phong_n" + std::to_string(int(n)), gpu::WARP_PHONG_LOBE, float(n), cap,
                            [n](glm::dvec3 d) { return phongReference(d, n); }, 1e-5 + 1e-7 * n,
                            1e-6 * (n + 1.0) / (2.0 * kPi)},
                           seed++);
    }
}

TEST(Warp, UniformSphere) {
    checkDirectionWarp({"uniform_sphere", gpu::WARP_UNIFORM_SPHERE, 0.0f, 2.0,
                        [](glm::dvec3) { return 1.0 / (4.0 * kPi); }},
                       10);
}

TEST(Warp, UniformCone) {
    // Given cos(thetaMax): a moderate cone, a near-hemisphere and a cone wider than a
    // hemisphere. The cap is 1 - cos(thetaMax) as float arithmetic on the GPU forms it,
    // so the cone's edge falls exactly on a row edge of the histogram.
    uint32_t seed = 20;
    for (float cosMax : {0.9f, 0.01f, -0.5f}) {
        SCOPED_TRACE("cosThetaMax = " + std::to_string(cosMax));
        const double cap = double(1.0f - cosMax);
        checkDirectionWarp(coneCase("cone_cos" + std::to_string(cosMax), gpu::WARP_UNIFORM_CONE, cosMax, cap), seed++);
    }
    // Given 1 - cos(thetaMax): a sphere light of radius r at distance d subtends
    // 1 - cos ~ r^2 / (2 d^2); 10^-5 is below what cos(thetaMax) itself can hold in float
    // to better than 1%.
    for (float oneMinusCosMax : {1e-2f, 1e-5f}) {
        SCOPED_TRACE("1 - cosThetaMax = " + std::to_string(oneMinusCosMax));
        checkDirectionWarp(coneCase("cone_1m" + std::to_string(oneMinusCosMax), gpu::WARP_UNIFORM_CONE_1M,
                                    oneMinusCosMax, double(oneMinusCosMax)),
                           seed++);
    }
}

// ---- Planar warps, tested on the unit square through an explicit parameterization --------

TEST(Warp, UniformDisk) {
    // (s, t) = (r^2, phi / 2 pi): dA = r dr dphi = pi ds dt, so the density in (s, t) is
    // pi p_A, uniform (= 1) for the uniform disk.
    auto& k = warpKernel();
    const auto samples = k.sample(gpu::WARP_UNIFORM_DISK, 0.0f, 30);
    std::vector<glm::dvec2> points(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
        const glm::vec4 s = samples[i];
        ASSERT_TRUE(s.w > 0.0f && std::abs(s.w - 1.0 / kPi) < 1e-6) << "sample " << i << " pdf " << s.w;
        double phi = std::atan2(double(s.y), double(s.x));
        if (phi < 0.0) phi += 2.0 * kPi;
        points[i] = {double(s.x) * s.x + double(s.y) * s.y, phi / (2.0 * kPi)};
    }
    test::SquareChi2Options options{64, kAlpha, kChi2Tests, "chi2_uniform_disk"};
    const auto r = test::chi2TestSquare(
        points,
        [&k](const std::vector<glm::dvec2>& st) {
            std::vector<glm::vec4> p(st.size());
            for (size_t i = 0; i < st.size(); ++i) {
                const double r = std::sqrt(st[i].x), phi = 2.0 * kPi * st[i].y;
                p[i] = glm::vec4(float(r * std::cos(phi)), float(r * std::sin(phi)), 0.0f, 0.0f);
            }
            auto values = k.pdf(gpu::WARP_UNIFORM_DISK, 0.0f, p);
            for (double& v : values) v *= kPi;
            return values;
        },
        options);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, r.integralTolerance) << r.message;
    std::printf("[ uniform_disk ] %s\n", r.message.c_str());
}

TEST(Warp, UniformTriangle) {
    // Barycentrics (b0, b1) -> (s, t) = (b0 + b1, b1 / (b0 + b1)), i.e. b0 = s (1 - t),
    // b1 = s t with Jacobian s. A triangle of area A has dA = 2 A db0 db1 = 2 A s ds dt,
    // so the density in (s, t) is 2 A s p_A = 2 s for the uniform density p_A = 1/A.
    const float area = 3.7f;  // any area: p_A must scale as 1/A
    auto& k = warpKernel();
    const auto samples = k.sample(gpu::WARP_UNIFORM_TRIANGLE, area, 31);
    std::vector<glm::dvec2> points(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
        const glm::vec4 b = samples[i];
        ASSERT_TRUE(b.x >= 0.0f && b.y >= 0.0f && b.z >= 0.0f && std::abs(b.x + b.y + b.z - 1.0f) < 1e-6f)
            << "sample " << i << " barycentrics " << b.x << ", " << b.y << ", " << b.z;
        ASSERT_NEAR(b.w, 1.0 / area, 1e-6) << "sample " << i;
        const double s = double(b.x) + double(b.y);
        points[i] = {s, s > 0.0 ? double(b.y) / s : 0.0};
    }
    test::SquareChi2Options options{64, kAlpha, kChi2Tests, "chi2_uniform_triangle"};
    const auto r = test::chi2TestSquare(
        points,
        [&k, area](const std::vector<glm::dvec2>& st) {
            std::vector<glm::vec4> p(st.size());
            for (size_t i = 0; i < st.size(); ++i) {
                const double s = st[i].x, t = st[i].y;
                p[i] = glm::vec4(float(s * (1.0 - t)), float(s * t), float(1.0 - s), 0.0f);
            }
            auto values = k.pdf(gpu::WARP_UNIFORM_TRIANGLE, area, p);
            for (size_t i = 0; i < values.size(); ++i) values[i] *= 2.0 * area * st[i].x;
            return values;
        },
        options);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, r.integralTolerance) << r.message;
    std::printf("[ uniform_triangle ] %s\n", r.message.c_str());
}

// ---- The harness rejects wrong pdfs (test of the test) ------------------------------------

TEST(Chi2, RejectsCosineSamplesAgainstUniformPdf) {
    // Both densities integrate to 1 on the hemisphere, so only the histogram can tell.
    auto& k = warpKernel();
    const auto samples = k.sample(gpu::WARP_COSINE_HEMISPHERE, 0.0f, 40);
    test::SphereChi2Options options;
    options.capOneMinusCos = 1.0;
    options.significance = kAlpha;
    options.numTests = kChi2Tests;
    options.dumpName = "chi2_expected_failure_cosine_vs_uniform";
    const auto r = test::chi2TestSphere(directionsOf(samples), k.directionPdf(gpu::WARP_UNIFORM_HEMISPHERE, 0.0f),
                                        options);
    EXPECT_FALSE(r.passed) << r.message;
    EXPECT_LT(r.pValue, r.threshold) << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, r.integralTolerance) << r.message;
    std::printf("[ expected failure ] %s\n", r.message.c_str());
}

TEST(Chi2, RejectsPhongSamplesAgainstBrdfNormalisation) {
    // cos^n lobe samples checked against (n+2)/(2 pi) cos^n, the BRDF normalisation, which
    // is not a density in solid angle: it integrates to (n+2)/(n+1).
    auto& k = warpKernel();
    for (double n : {1.0, 10.0, 1000.0}) {
        SCOPED_TRACE("n = " + std::to_string(n));
        const auto samples = k.sample(gpu::WARP_PHONG_LOBE, float(n), 41);
        test::SphereChi2Options options;
        options.capOneMinusCos = std::min(1.0, 8.0 / (n + 1.0));
        options.significance = kAlpha;
        options.numTests = kChi2Tests;
        options.dumpName = "chi2_expected_failure_phong_n" + std::to_string(int(n)) + "_plus2";
        const auto r = test::chi2TestSphere(
            directionsOf(samples), k.directionPdf(gpu::WARP_PHONG_LOBE, float(n), (n + 2.0) / (n + 1.0)), options);
        EXPECT_FALSE(r.passed) << r.message;
        EXPECT_NEAR(r.pdfIntegral, (n + 2.0) / (n + 1.0), r.integralTolerance) << r.message;
        EXPECT_GT(std::abs(r.pdfIntegral - 1.0), r.integralTolerance) << r.message;
        std::printf("[ expected failure ] %s\n", r.message.c_str());
    }
}

TEST(Chi2, RejectsSamplesOutsideTheSupport) {
    // Uniform sphere samples checked against the uniform hemisphere pdf: half the samples
    // land where the pdf integrates to 0.
    auto& k = warpKernel();
    const auto samples = k.sample(gpu::WARP_UNIFORM_SPHERE, 0.0f, 42);
    test::SphereChi2Options options;
    options.capOneMinusCos = 1.0;
    options.numTests = kChi2Tests;
    options.dumpName = "chi2_expected_failure_sphere_vs_hemisphere";
    const auto r = test::chi2TestSphere(directionsOf(samples), k.directionPdf(gpu::WARP_UNIFORM_HEMISPHERE, 0.0f),
                                        options);
    EXPECT_FALSE(r.passed) << r.message;
    EXPECT_NE(r.message.find("outside its support"), std::string::npos) << r.message;
}
