// bsdfSample / bsdfPdf / bsdfEval of shaders/bsdf/bsdf.glsl, run as GLSL on lavapipe
// (shaders/tests/bsdf_sampling.comp), for diffuse and Phong materials (pure diffuse, pure
// glossy, 50/50 and a glossy-heavy mix; exponents 1, 20, 200, 5000) seen from normal
// incidence, 45 degrees and grazing (cos theta_o = 0.05):
//   - bsdfSample's directions pass a chi-square test against bsdfPdf;
//   - bsdfPdf integrates to 1 minus the glossy mass that falls below the surface (those
//     samples are declined): <= 1 always, = 1 for diffuse and at normal incidence, where the
//     lobe about the mirror direction n is cut exactly by the horizon at alpha = 90 degrees;
//   - the pdf bsdfSample returns is bsdfPdf at its direction;
//   - bsdfEval is reciprocal, f(wo, wi) = f(wi, wo);
//   - the albedo integral f cos d(omega) is <= kd + ks per channel, and at normal incidence
//     equals kd + ks for every exponent: the glossy lobe there is cos^n(theta), and
//     (n+2)/(2 pi) integral cos^(n+1) d(omega) = (n+2)/(2 pi) * 2 pi / (n+2) = 1 exactly.
//
// The histogram's chart. Directions are in the frame of n, (theta, phi). A narrow lobe near
// the horizon would fall in a handful of the sphere harness's cells, and its cut by the
// horizon would cross cells, which the Gauss-Legendre cells cannot integrate. So the chart
// is the unit square with s = F(theta) on [0, pi/2] and t = G(phi) on a full turn centred
// on the lobe, F and G monotone blends of a linear map and an arctangent of width ~ the
// lobe's angular radius 1/sqrt(n+1): 70% of the cells resolve the lobe, the horizon is the
// edge s = 1, and the density in (s, t) is p(omega) sin(theta) / (F'(theta) G'(phi)).
//
// Significance: alpha = 0.01 for the file, Sidak-corrected over kChi2Tests tests; fixed seeds.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bsdf_test_kernel.h"
#include "chi2.h"
#include "test_frame.h"
#include "tests/bsdf_sampling_test.h"

using namespace penumbra;
using glm::dvec2;
using glm::dvec3;
using glm::vec3;
using gpu::BsdfTestRecord;
using test::bsdfKernel;
using test::Chart;
using test::makePush;

namespace {

constexpr double kAlpha = 0.01;
constexpr int kMaterials = 10;
constexpr int kAngles = 3;
constexpr int kChi2Tests = kMaterials * kAngles;
constexpr uint32_t kSamples = 1u << 20;
constexpr double kPi = std::numbers::pi;

static_assert(sizeof(gpu::BsdfTestPush) == 80 && sizeof(BsdfTestRecord) == 32);

// ---- Cases ----------------------------------------------------------------------------------------

struct MaterialCase {
    std::string name;
    gpu::Material m;
};

std::vector<MaterialCase> materials() {
    std::vector<MaterialCase> out;
    out.push_back({"diffuse", {vec3(0.8f, 0.5f, 0.2f), gpu::MATERIAL_DIFFUSE, vec3(0.0f), 0.0f}});
    for (float n : {1.0f, 20.0f, 200.0f, 5000.0f})
        out.push_back({"glossy_n" + std::to_string(int(n)), {vec3(0.0f), gpu::MATERIAL_PHONG, vec3(0.9f, 0.7f, 0.5f), n}});
    for (float n : {1.0f, 20.0f, 200.0f, 5000.0f})
        out.push_back({"half_n" + std::to_string(int(n)), {vec3(0.45f), gpu::MATERIAL_PHONG, vec3(0.45f), n}});
    out.push_back({"mix_n20", {vec3(0.1f, 0.2f, 0.05f), gpu::MATERIAL_PHONG, vec3(0.7f, 0.6f, 0.9f), 20.0f}});
    return out;
}

double meanOf(vec3 v) { return (double(v.x) + v.y + v.z) / 3.0; }

// The normal is tilted so that the frames are general; wo is at angle theta_o from it.
const dvec3 kNormal = glm::normalize(dvec3(0.3, -0.5, 0.8));

vec3 outgoing(double cosTheta) {
    const test::Frame f(kNormal);
    const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
    return vec3(glm::normalize(f.toWorld({sinTheta * std::cos(0.7), sinTheta * std::sin(0.7), cosTheta})));
}

// The chart for a material and wo: focused on the mirror direction for a glossy lobe
// narrower than ~30 degrees (angular radius ~ 1/sqrt(n+1)), linear otherwise.
Chart chartFor(const gpu::Material& m, vec3 wo, vec3 n) {
    const bool glossy = m.type == gpu::MATERIAL_PHONG && meanOf(m.ks) > 0.0;
    return test::mirrorChart(wo, n, glossy ? 1.0 / std::sqrt(double(m.exponent) + 1.0) : 1.0);
}

// Probability that the cos^n lobe about the mirror direction r falls below the surface, r at
// elevation beta above it (sin(beta) = cos(theta_o)): in the lobe's frame (alpha, phi), a
// direction is below when cos(alpha) sin(beta) + sin(alpha) cos(beta) cos(phi) < 0, i.e. for
// alpha > beta on a share acos(tan(beta) / tan(alpha)) / pi of the turn. Midpoint rule on a
// fine grid (the lobe is >= 1/sqrt(5001) wide, the grid 1e-5 rad), double precision.
double lobeMassBelow(double n, double cosThetaO) {
    const double beta = std::asin(std::clamp(cosThetaO, 0.0, 1.0));
    if (beta >= 0.5 * kPi) return 0.0;
    const int steps = 200000;
    const double h = (0.5 * kPi - beta) / steps;
    double sum = 0.0;
    for (int i = 0; i < steps; ++i) {
        const double a = beta + (i + 0.5) * h;
        sum += (n + 1.0) * std::pow(std::cos(a), n) * std::sin(a) * std::acos(std::tan(beta) / std::tan(a)) / kPi * h;
    }
    return sum;
}

}  // namespace

// ---- The tests -----------------------------------------------------------------------------------

class BsdfSampling : public ::testing::TestWithParam<int> {};

TEST_P(BsdfSampling, ChiSquarePdfReciprocityAndEnergy) {
    const MaterialCase mc = materials()[GetParam()];
    const gpu::Material& m = mc.m;
    const vec3 n(kNormal);
    auto& kernel = bsdfKernel();
    int angle = 0;
    for (double cosTheta : {1.0, std::sqrt(0.5), 0.05}) {
        const std::string name = mc.name + "_cos" + std::to_string(cosTheta).substr(0, 4);
        SCOPED_TRACE(name);
        const vec3 wo = cosTheta == 1.0 ? n : outgoing(cosTheta);
        const uint32_t seed = 1000 + 10 * uint32_t(GetParam()) + uint32_t(angle++);
        const auto samples = kernel.run(makePush(m, n, wo, gpu::BSDF_TEST_MODE_SAMPLE, kSamples, seed), {});

        // The returned pdf is bsdfPdf at the returned direction, and positive; the returned
        // f is bsdfEval there (the same evaluation: exactly).
        size_t declined = 0, badPdf = 0, badF = 0;
        for (const auto& s : samples) {
            if (s.a == glm::vec4(0.0f)) {
                ++declined;
                continue;
            }
            if (!(s.a.w > 0.0f) || s.a.w != s.b.x) ++badPdf;
            if (s.b.y != 0.0f || s.b.z != 0.0f || s.b.w != 0.0f) ++badF;
        }
        EXPECT_EQ(badPdf, 0u) << name << ": bsdfSample's pdf differs from bsdfPdf";
        EXPECT_EQ(badF, 0u) << name << ": bsdfSample's f differs from bsdfEval";

        // Chi-square in the lobe's chart.
        const Chart chart = chartFor(m, wo, n);
        const std::vector<dvec2> points = test::chartPoints(chart, samples);
        // bsdfPdf's glossy term rounds cos(alpha) (a dot product near 1: <= 3 * 2^-24), which
        // cos^n turns into n * 3 * 2^-24 relative: a bound on its integral's float error.
        const double glossyShare = m.type == gpu::MATERIAL_PHONG && meanOf(m.ks) > 0.0
                                       ? meanOf(m.ks) / (meanOf(m.kd) + meanOf(m.ks))
                                       : 0.0;
        test::SquareChi2Options options{64, kAlpha, kChi2Tests, "chi2_bsdf_" + name,
                                        glossyShare * double(m.exponent) * 3.0 * std::ldexp(1.0, -24)};
        // The mass bsdfSample declines: the glossy lobe's part below the surface.
        const double declinedMass = glossyShare * lobeMassBelow(m.exponent, cosTheta);
        options.declinedFraction = declinedMass;
        const auto r = test::chi2TestSquare(points, test::chartPdf(kernel, m, n, wo, chart), options);
        EXPECT_TRUE(r.passed) << name << ": " << r.message;
        // <= 1; 1 for diffuse and at normal incidence (declinedMass = 0 there); else 1 minus
        // the glossy mass below the surface.
        EXPECT_LE(r.pdfIntegral, 1.0 + r.integralTolerance) << name << ": " << r.message;
        EXPECT_NEAR(r.pdfIntegral, 1.0 - declinedMass, r.integralTolerance) << name << ": " << r.message;
        if (m.type == gpu::MATERIAL_DIFFUSE || cosTheta == 1.0) {
            EXPECT_EQ(declinedMass, 0.0);
        }

        // Reciprocity and the albedo, from bsdfEval at the sampled pairs. Reciprocity: the two
        // evaluations form cos(alpha) from the mirror of wo or of wi, which differ by the
        // rounding of a reflection and a dot product, delta <= 8 * 2^-24; cos^n moves by
        // n cos^(n-1) delta, and its exp/log evaluation is good to 2e-6 relative (warp.glsl).
        // So |f(wo, wi) - f(wi, wo)| <= ks (n+2)/(2 pi) (n cos^(n-1) delta + 2e-6 cos^n)
        // + 1e-6 f (the diffuse term and the final products).
        std::vector<BsdfTestRecord> pairs(samples.size());
        for (size_t i = 0; i < samples.size(); ++i) pairs[i] = {glm::vec4(wo, 0.0f), glm::vec4(vec3(samples[i].a), 0.0f)};
        const auto f = kernel.run(makePush(m, n, wo, gpu::BSDF_TEST_MODE_EVAL, kSamples, 0), pairs);
        size_t notReciprocal = 0;
        glm::dvec3 sum(0.0), sum2(0.0);
        for (size_t i = 0; i < samples.size(); ++i) {
            if (samples[i].a == glm::vec4(0.0f)) continue;
            const dvec3 wi(vec3(samples[i].a));
            const dvec3 mirror = 2.0 * glm::dot(dvec3(wo), dvec3(n)) * dvec3(n) - dvec3(wo);
            const double cosAlpha = std::clamp(glm::dot(wi, mirror), 0.0, 1.0), e = double(m.exponent);
            const double delta = 8.0 * std::ldexp(1.0, -24);
            const double lobe = (e + 2.0) / (2.0 * kPi) *
                                (e * std::pow(cosAlpha + delta, std::max(e - 1.0, 0.0)) * delta +
                                 2e-6 * std::pow(cosAlpha + delta, e));
            for (int c = 0; c < 3; ++c) {
                const double tolerance = double(m.ks[c]) * lobe + 1e-6 * std::max(f[i].a[c], f[i].b[c]);
                if (std::abs(double(f[i].a[c]) - f[i].b[c]) > tolerance) ++notReciprocal;
            }
            // Albedo estimator f cos / pdf: unbiased for the integral over the pdf's support,
            // which holds all of f's (glossy f vanishes where its lobe does).
            const glm::dvec3 w = glm::dvec3(glm::vec3(f[i].a)) * glm::dot(wi, dvec3(n)) / double(samples[i].a.w);
            sum += w;
            sum2 += w * w;
        }
        EXPECT_EQ(notReciprocal, 0u) << name << ": f(wo, wi) != f(wi, wo)";
        const double N = double(samples.size());
        const glm::dvec3 albedo = sum / N, sigma = glm::sqrt(glm::max(sum2 / N - albedo * albedo, 0.0) / N);
        // 5 standard errors: a chance failure has probability < 1e-6 per channel.
        for (int c = 0; c < 3; ++c) {
            const double bound = double(m.kd[c]) + double(m.ks[c]);
            EXPECT_LE(albedo[c], bound + 5.0 * sigma[c] + 1e-6) << name << " channel " << c;
            if (cosTheta == 1.0) {
                EXPECT_NEAR(albedo[c], bound, 5.0 * sigma[c] + 1e-6) << name << " channel " << c;
            }
        }
        std::printf("[ %s ] declined %.5f (%.5f), albedo (%.5f %.5f %.5f) +- %.1e; %s\n", name.c_str(), declined / N,
                    declinedMass, albedo.x, albedo.y, albedo.z, sigma.x, r.message.c_str());
    }
}

INSTANTIATE_TEST_SUITE_P(Materials, BsdfSampling, ::testing::Range(0, kMaterials),
                         [](const ::testing::TestParamInfo<int>& info) { return materials()[info.param].name; });
