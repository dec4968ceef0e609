// The `pbr` BRDF of shaders/bsdf/pbr.glsl, run as GLSL on lavapipe through the BSDF test
// kernel, for roughness 0.01 to 1, metallic 0 and 1, seen from normal incidence, 45 degrees
// and grazing (cos theta_o = 0.05); base colour (1, 0.7, 0.4), so that channel 0 is white:
//   - bsdfSample's directions pass a chi-square test against bsdfPdf (the full mixture);
//   - bsdfPdf integrates to the mass bsdfSample keeps (specular samples reflected below the
//     surface are declined): within the binomial error of the declined count, and equal to
//     1 minus the declined share integrated on the CPU;
//   - the pdf bsdfSample returns is bsdfPdf at its direction; bsdfPdf and bsdfEval equal
//     the contract's formula (tests/pbr_reference.h, double precision) to float accuracy;
//   - a wrong pdf (plain NDF sampling's density) fails the same chi-square test;
//   - bsdfEval is reciprocal and non-negative, never NaN or infinite;
//   - white furnace: the albedo of channel 0 equals the contract formula's, integrated on
//     the CPU (Monte Carlo and quadrature errors both bounded), and for metallic 1 (GGX's
//     single-scattering albedo) is <= 1;
//   - roughness 0 (clamped to PBR_MIN_ALPHA) at normal and grazing angles stays finite.
// Significance: alpha = 0.01 for the file, Sidak-corrected over the chi-square tests; fixed seeds.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bsdf_test_kernel.h"
#include "chi2.h"
#include "pbr_reference.h"

using namespace penumbra;
using glm::dvec2;
using glm::dvec3;
using glm::vec3;
using gpu::BsdfTestRecord;
using test::bsdfKernel;
using test::Chart;
using test::FocusMap;
using test::makePush;

namespace {

constexpr double kAlpha = 0.01;
constexpr double kRoughness[] = {0.01, 0.1, 0.5, 1.0};
constexpr double kMetallic[] = {0.0, 1.0};
constexpr double kCosines[] = {1.0, 0.70710678118654752, 0.05};
constexpr int kCases = 4 * 2;
constexpr int kChi2Tests = kCases * 3;
constexpr uint32_t kSamples = 1u << 20;
constexpr double kPi = std::numbers::pi;
const vec3 kBase(1.0f, 0.7f, 0.4f);

// The normal is tilted so that the frames are general; wo is at angle theta_o from it.
const dvec3 kNormal = glm::normalize(dvec3(0.3, -0.5, 0.8));

vec3 outgoing(double cosTheta) {
    if (cosTheta == 1.0) return vec3(kNormal);
    const test::Frame f(kNormal);
    const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
    return vec3(glm::normalize(f.toWorld({sinTheta * std::cos(0.7), sinTheta * std::sin(0.7), cosTheta})));
}

gpu::Material pbrMaterial(vec3 base, float metallic, float roughness) {
    return {base, gpu::MATERIAL_PBR, vec3(metallic, roughness, 0.0f), 0.0f};
}

test::PbrParams paramsOf(const gpu::Material& m) {
    test::PbrParams p;
    p.baseColor = dvec3(m.kd);
    p.metallic = m.ks.x;
    p.roughness = m.ks.y;
    return p;
}

// Angular error of a float direction (a few roundings of 2^-24 on unit vectors). The half
// vector (wo + wi) / |wo + wi| divides it by |wo + wi| / 2 = wo.h (the tangential parts of
// wo and wi cancel exactly, Sterbenz), and D's relative error is 2 / alpha per radian of h
// (|d ln D / d theta_h| is largest, 2 / alpha, at theta_h = alpha); 1e-5 covers the ~20
// roundings of the rest of f and the pdf.
constexpr double kDirectionError = 4.0 * 5.96e-8;
double dRelativeError(double alpha, double vDotH) { return 2.0 * kDirectionError / (alpha * vDotH) + 1e-5; }
double vDotH(dvec3 wo, dvec3 wi) { return 0.5 * glm::length(glm::normalize(wo) + glm::normalize(wi)); }

// Focused on the mirror direction when the specular lobe (angular radius ~ 2 alpha in wi)
// is narrower than ~30 degrees, linear otherwise.
Chart chartFor(double alpha, vec3 wo, vec3 n) { return test::mirrorChart(wo, n, 2.0 * alpha); }

// Channel 0 of the albedo, the integral of f cos over the hemisphere, in the chart (midpoint
// rule, N x N cells): the horizon is the chart's edge s = 1 and a narrow lobe gets most
// cells, so the integrand is smooth inside every cell and the rule converges as 1/N^2.
struct ChartIntegrals {
    double albedo = 0.0;
};

ChartIntegrals integrateInChart(const Chart& chart, const test::PbrParams& p, dvec3 n, dvec3 wo, int N) {
    ChartIntegrals out;
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) {
            double jac;
            const dvec3 wi = chart.fromChart({(i + 0.5) / N, (j + 0.5) / N}, jac);
            const double cosI = glm::dot(n, wi);
            if (cosI <= 0.0) continue;
            out.albedo += test::pbrF(p, n, wo, wi).x * cosI * jac;
        }
    out.albedo /= double(N) * N;
    return out;
}

// The specular lobe's mass below the surface (what bsdfSample declines, divided by the lobe's
// probability): the reflected visible normals' density G1 D(h) / (4 cos(theta_o)) (Heitz 2018)
// over the directions wi below the surface whose half vector is above it, i.e. theta_i in
// (pi/2, pi - theta_o). Midpoint rule on N x 2N cells of (theta, phi), each squeezed by a
// FocusMap onto the horizon and the mirror azimuth where the lobe is narrow: both bounds
// are cell edges and the integrand is smooth in every cell.
double specularMassBelow(const test::PbrParams& p, dvec3 n, dvec3 wo, int N) {
    const test::Frame frame(n);
    wo = glm::normalize(wo);
    const dvec3 local = frame.toLocal(wo);
    const double a = p.alpha(), cosO = local.z, thetaO = std::acos(std::min(cosO, 1.0));
    const double g1 = 2.0 * cosO / (cosO + std::sqrt(a * a + (1.0 - a * a) * cosO * cosO));
    const double width = 2.0 * a < 0.5 ? 2.0 * a : 0.0, phiC = std::atan2(local.y, local.x) + kPi;
    const FocusMap theta(0.5 * kPi, kPi - thetaO, 0.5 * kPi, width), phi(phiC - kPi, phiC + kPi, phiC, width);
    std::vector<double> ts(N), tw(N), ps(2 * N), pw(2 * N);
    for (int i = 0; i < N; ++i) {
        ts[i] = theta.inverse((i + 0.5) / N);
        tw[i] = std::sin(ts[i]) / (theta.derivative(ts[i]) * N);
    }
    for (int j = 0; j < 2 * N; ++j) {
        ps[j] = phi.inverse((j + 0.5) / (2 * N));
        pw[j] = 1.0 / (phi.derivative(ps[j]) * 2 * N);
    }
    double sum = 0.0;
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < 2 * N; ++j) {
            const dvec3 wi =
                frame.toWorld({std::sin(ts[i]) * std::cos(ps[j]), std::sin(ts[i]) * std::sin(ps[j]), std::cos(ts[i])});
            const dvec3 h = glm::normalize(wo + wi);
            sum += g1 * test::ggxD(a, glm::dot(frame.n, h)) / (4.0 * cosO) * tw[i] * pw[j];
        }
    return sum;
}

}  // namespace

class PbrSampling : public ::testing::TestWithParam<int> {};

TEST_P(PbrSampling, ChiSquarePdfFormulaReciprocityAndFurnace) {
    const double roughness = kRoughness[GetParam() / 2], metallic = kMetallic[GetParam() % 2];
    const gpu::Material m = pbrMaterial(kBase, float(metallic), float(roughness));
    const test::PbrParams ref = paramsOf(m);
    const double alpha = ref.alpha();
    const vec3 n(kNormal);
    auto& kernel = bsdfKernel();
    int angle = 0;
    for (double cosTheta : kCosines) {
        const std::string name = "pbr_r" + std::to_string(roughness).substr(0, 4) + "_m" +
                                 std::to_string(int(metallic)) + "_cos" + std::to_string(cosTheta).substr(0, 4);
        SCOPED_TRACE(name);
        const vec3 wo = outgoing(cosTheta);
        const uint32_t seed = 5000 + 10 * uint32_t(GetParam()) + uint32_t(angle++);
        const auto samples = kernel.run(makePush(m, n, wo, gpu::BSDF_TEST_MODE_SAMPLE, kSamples, seed), {});

        // The returned pdf is bsdfPdf at the returned direction, positive and finite; and
        // bsdfPdf is the documented density (tests/pbr_reference.h) to float accuracy.
        size_t declined = 0, badPdf = 0, pdfMismatch = 0;
        for (const auto& s : samples) {
            if (s.a == glm::vec4(0.0f)) {
                ++declined;
                continue;
            }
            if (!(s.a.w > 0.0f) || !std::isfinite(s.a.w) || s.a.w != s.b.x) ++badPdf;
            const double expected = test::pbrPdf(ref, dvec3(n), dvec3(wo), glm::normalize(dvec3(vec3(s.a))));
            const dvec3 wi(vec3(s.a));
            if (std::abs(s.a.w - expected) > dRelativeError(alpha, vDotH(dvec3(wo), wi)) * expected + 1e-6)
                ++pdfMismatch;
        }
        EXPECT_EQ(badPdf, 0u) << name << ": bsdfSample's pdf differs from bsdfPdf or is not positive and finite";
        EXPECT_EQ(pdfMismatch, 0u) << name << ": bsdfPdf differs from the documented mixture density";

        const Chart chart = chartFor(alpha, wo, n);
        const std::vector<dvec2> points = test::chartPoints(chart, samples);
        const test::SquarePdf gpuPdf = test::chartPdf(kernel, m, n, wo, chart);
        // The pdf's float evaluation error: D's relative error from the half vector's, at the
        // smallest wo.h of the lobe (about cos(theta_o) at the mirror direction, halved for margin).
        test::SquareChi2Options options{64, kAlpha, kChi2Tests, "chi2_" + name, dRelativeError(alpha, 0.5 * cosTheta)};
        // The declined share and the albedo, integrated on the CPU (their error: twice the
        // change from N to 2N cells).
        const ChartIntegrals q1 = integrateInChart(chart, ref, dvec3(n), dvec3(wo), 256);
        const ChartIntegrals q2 = integrateInChart(chart, ref, dvec3(n), dvec3(wo), 512);
        const double pSpecular = test::pbrSpecularProbability(ref, cosTheta);
        const double declinedQ1 = pSpecular * specularMassBelow(ref, dvec3(n), dvec3(wo), 256);
        const double declinedQ2 = pSpecular * specularMassBelow(ref, dvec3(n), dvec3(wo), 512);
        options.declinedFraction = declinedQ2;
        const auto r = test::chi2TestSquare(points, gpuPdf, options);
        EXPECT_TRUE(r.passed) << name << ": " << r.message;
        // The pdf's mass is what bsdfSample keeps: 1 - declined / N within 5 binomial
        // standard errors (a chance failure < 1e-6), and 1 - the CPU's declined share
        // within the quadratures' bounds.
        const double N = double(samples.size()), kept = 1.0 - double(declined) / N;
        const double binomial = 5.0 * std::sqrt(std::max(kept * (1.0 - kept), 1.0 / N) / N);
        EXPECT_LE(r.pdfIntegral, 1.0 + r.integralTolerance) << name << ": " << r.message;
        EXPECT_NEAR(r.pdfIntegral, kept, binomial + r.integralTolerance) << name << ": " << r.message;
        EXPECT_NEAR(r.pdfIntegral, 1.0 - declinedQ2, r.integralTolerance + 2.0 * std::abs(declinedQ2 - declinedQ1))
            << name << ": " << r.message;

        // A wrong pdf fails: plain NDF sampling's density in place of the visible normals',
        // where the two differ most: rough metal (all samples specular) seen off the normal.
        if (metallic == 1.0 && roughness >= 0.5 && cosTheta < 1.0) {
            test::SquareChi2Options wrong = options;
            wrong.dumpName = "chi2_wrong_" + name;
            wrong.numTests = 1;
            const auto w = test::chi2TestSquare(
                points,
                [&](const std::vector<dvec2>& st) {
                    std::vector<double> values(st.size());
                    for (size_t i = 0; i < st.size(); ++i) {
                        double jac;
                        const dvec3 wi = chart.fromChart(st[i], jac);
                        values[i] = test::pbrPdf(ref, dvec3(n), dvec3(wo), wi, true) * jac;
                    }
                    return values;
                },
                wrong);
            EXPECT_FALSE(w.passed) << name << ": the NDF density passed for the VNDF samples: " << w.message;
        }

        // f at the sampled pairs and swapped: reciprocal, non-negative, finite, equal to the
        // contract's formula. Reciprocity: both evaluations form the same half vector and
        // |wo + wi| (commutative float sums), and `precise` (shaders/bsdf/pbr.glsl) keeps a
        // driver from fusing the two evaluations' products differently (an NVIDIA H200
        // did, before); the bound allows a few roundings of 2^-24, relative.
        std::vector<BsdfTestRecord> pairs(samples.size());
        for (size_t i = 0; i < samples.size(); ++i)
            pairs[i] = {glm::vec4(wo, 0.0f), glm::vec4(vec3(samples[i].a), 0.0f)};
        const auto f = kernel.run(makePush(m, n, wo, gpu::BSDF_TEST_MODE_EVAL, kSamples, 0), pairs);
        size_t notReciprocal = 0, negative = 0, formula = 0;
        dvec3 sum(0.0), sum2(0.0);
        for (size_t i = 0; i < samples.size(); ++i) {
            if (samples[i].a == glm::vec4(0.0f)) continue;
            const dvec3 wi = glm::normalize(dvec3(vec3(samples[i].a)));
            const dvec3 expected = test::pbrF(ref, dvec3(n), dvec3(wo), wi);
            for (int c = 0; c < 3; ++c) {
                const double a = f[i].a[c], b = f[i].b[c];
                if (!(a >= 0.0) || !(b >= 0.0) || !std::isfinite(a) || !std::isfinite(b)) ++negative;
                if (std::abs(a - b) > 4.0 * 5.96e-8 * std::max(a, b)) ++notReciprocal;
                if (std::abs(a - expected[c]) > dRelativeError(alpha, vDotH(dvec3(wo), wi)) * expected[c] + 1e-6)
                    ++formula;
            }
            const dvec3 w = dvec3(vec3(f[i].a)) * glm::dot(wi, dvec3(n)) / double(samples[i].a.w);
            sum += w;
            sum2 += w * w;
        }
        EXPECT_EQ(negative, 0u) << name << ": f negative, NaN or infinite";
        EXPECT_EQ(notReciprocal, 0u) << name << ": f(wo, wi) != f(wi, wo)";
        EXPECT_EQ(formula, 0u) << name << ": f differs from the contract's formula";

        // White furnace on channel 0 (base colour 1): the albedo equals the contract's
        // formula integrated on the CPU, within 5 standard errors (< 1e-6 by chance) plus
        // twice the quadrature's change from N to 2N cells; for metallic 1 it is GGX's
        // single-scattering albedo, <= 1. (The dielectric's is not bounded by 1: glTF's
        // (1 - F(v.h)) diffuse weight is not 1 minus the specular albedo; docs/guide/materials.md.)
        const dvec3 albedo = sum / N, sigma = glm::sqrt(glm::max(sum2 / N - albedo * albedo, 0.0) / N);
        const double quadratureError = 2.0 * std::abs(q2.albedo - q1.albedo);
        EXPECT_NEAR(albedo.x, q2.albedo, 5.0 * sigma.x + quadratureError + 1e-6) << name;
        if (metallic == 1.0) {
            EXPECT_LE(albedo.x, 1.0 + 5.0 * sigma.x + 1e-6) << name;
            EXPECT_LE(q2.albedo, 1.0 + quadratureError) << name;
        }
        const double quadrature = q2.albedo;
        std::printf("[ %s ] declined %.5f, albedo %.5f +- %.1e (quadrature %.5f); %s\n", name.c_str(), declined / N,
                    albedo.x, sigma.x, quadrature, r.message.c_str());
    }
}

INSTANTIATE_TEST_SUITE_P(Materials, PbrSampling, ::testing::Range(0, kCases),
                         [](const ::testing::TestParamInfo<int>& info) {
                             // Appended, not "r" + ...: GCC 12 warns falsely (-Wrestrict) on
                             // a literal plus a temporary string.
                             std::string name = "r";
                             name += std::to_string(int(std::lround(100 * kRoughness[info.param / 2])));
                             name += "_m";
                             name += std::to_string(int(kMetallic[info.param % 2]));
                             return name;
                         });

// Roughness 0 is clamped to PBR_MIN_ALPHA: at normal incidence, where D peaks at
// 1 / (pi alpha^2), and at grazing angles, eval, pdf and sample stay finite.
TEST(PbrSampling, RoughnessZeroStaysFinite) {
    auto& kernel = bsdfKernel();
    const vec3 n(kNormal);
    for (float metallic : {0.0f, 1.0f}) {
        const gpu::Material m = pbrMaterial(vec3(1.0f), metallic, 0.0f);
        for (double cosTheta : {1.0, 0.05, 1e-4}) {
            const vec3 wo = outgoing(cosTheta);
            const vec3 mirror = glm::normalize(2.0f * glm::dot(wo, n) * n - wo);
            const auto s = kernel.run(makePush(m, n, wo, gpu::BSDF_TEST_MODE_SAMPLE, 4096, 7), {});
            for (const auto& r : s) EXPECT_TRUE(std::isfinite(r.a.w) && std::isfinite(r.b.x) && r.a.w >= 0.0f);
            const auto p =
                kernel.run(makePush(m, n, wo, gpu::BSDF_TEST_MODE_PDF, 3, 0),
                           {{glm::vec4(mirror, 0.0f), {}}, {glm::vec4(n, 0.0f), {}}, {glm::vec4(wo, 0.0f), {}}});
            for (const auto& r : p) EXPECT_TRUE(std::isfinite(r.a.x) && r.a.x >= 0.0f) << r.a.x;
            const auto f =
                kernel.run(makePush(m, n, wo, gpu::BSDF_TEST_MODE_EVAL, 2, 0),
                           {{glm::vec4(wo, 0.0f), glm::vec4(mirror, 0.0f)}, {glm::vec4(wo, 0.0f), glm::vec4(n, 0.0f)}});
            for (const auto& r : f)
                for (int c = 0; c < 3; ++c) {
                    EXPECT_TRUE(std::isfinite(r.a[c]) && r.a[c] >= 0.0f) << r.a[c];
                    EXPECT_TRUE(std::isfinite(r.b[c]) && r.b[c] >= 0.0f) << r.b[c];
                }
            // The mirror direction is the peak: f there is the contract's formula at alpha_min,
            // to the accuracy the float half vector allows (wo.h = cos(theta_o) here). At
            // cos(theta_o) = 1e-4 that bound exceeds 1: only finiteness is claimed there.
            const double bound = dRelativeError(gpu::PBR_MIN_ALPHA, cosTheta);
            const dvec3 expected = test::pbrF(paramsOf(m), dvec3(n), dvec3(wo), dvec3(mirror));
            if (bound < 0.5) {
                EXPECT_NEAR(f[0].a.x, expected.x, bound * expected.x) << "cos " << cosTheta;
            }
        }
    }
}
