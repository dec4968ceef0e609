// The direct-illumination integrator on `pbr` surfaces, against the contract's formula
// (tests/pbr_reference.h) integrated on the CPU, under light / bsdf / mis / mixture. The
// scenes put a pbr plane y = 0 under one light; the camera looks straight down from
// height 50, so wo(x) = normalize(eye - x), and each pixel's expected value is
//   point light        L(x) = f(wo, wi) I cos(theta_i) / d^2                     (exact)
//   quad light         L(x) = integral over the quad of f Le cos_i cos_l / r^2 dA
//                      (Gauss-Legendre, its convergence checked below)
//   constant env.      L(x) = Le integral over the hemisphere of f cos_i d(omega_i)
//                      (Gauss-Legendre in cos(theta_i) and phi)
// averaged over the pixel (render_helpers.h). The point light's estimate is the same for
// every sample of a pixel, so its variance is the spread over the pixel, known exactly; for
// the others a block t-test of the residuals checks unbiasedness (as test_direct.cpp does).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "many_light_scenes.h"
#include "pbr_reference.h"
#include "render_helpers.h"

using namespace penumbra;
using glm::dvec3;
using nlohmann::json;

namespace {

constexpr int kSize = 32;  // the film side of test::diffusePlaneScene
constexpr double kAlpha = 1e-3;
const std::vector<std::string> kStrategies = {"light", "bsdf", "mis", "mixture"};
const dvec3 kUp(0.0, 1.0, 0.0);

struct Surface {
    std::string name;
    test::PbrParams p;
};

// A rough dielectric and a smoother metal (channel 0 is what the helpers compare).
std::vector<Surface> surfaces() {
    test::PbrParams dielectric, metal;
    dielectric.baseColor = dvec3(0.7);
    dielectric.roughness = 0.5;
    metal.baseColor = dvec3(0.9, 0.6, 0.3);
    metal.metallic = 1.0;
    metal.roughness = 0.3;
    return {{"dielectric", dielectric}, {"metal", metal}};
}

json pbrJson(const test::PbrParams& p) {
    return {{"type", "pbr"},
            {"base_color", {p.baseColor.x, p.baseColor.y, p.baseColor.z}},
            {"metallic", p.metallic},
            {"roughness", p.roughness}};
}

// The patch [-1, 2] x [-1.5, 1.5] holds the highlight of a light above the origin: the
// many-light tests' diffuse plane (a kSize x kSize film) with the pbr material in its place.
json planeScene(const test::PbrParams& p, int spp) {
    json scene = test::diffusePlaneScene(spp, 23, 0.5, 1.5, 0.0);
    scene["materials"]["plane"] = pbrJson(p);
    scene["integrator"] = {{"type", "direct"}};
    return scene;
}

json direct(const std::string& strategy) { return {{"type", "direct"}, {"strategy", strategy}}; }

// Gauss-Legendre nodes and weights on [0, 1] (Newton on the Legendre recurrence).
void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.resize(n);
    w.resize(n);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            const double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-15) break;
        }
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp);  // 2 / ((1 - z^2) P'^2), halved for [0, 1]
    }
}

// Radiance toward the eye from a plane point lit by a quad light facing it, by an n x n
// Gauss-Legendre rule on the quad (origin + s u + t v).
double quadRadiance(const test::PbrParams& p, dvec3 eye, dvec3 x, dvec3 origin, dvec3 u, dvec3 v, double Le, int n) {
    std::vector<double> gx, gw;
    gaussLegendre(n, gx, gw);
    const dvec3 wo = glm::normalize(eye - x), cross = glm::cross(u, v);
    const double area = glm::length(cross);
    const dvec3 nl = cross / area;
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const dvec3 y = origin + gx[i] * u + gx[j] * v, d = y - x;
            const double r2 = glm::dot(d, d);
            const dvec3 wi = d / std::sqrt(r2);
            const double cosL = -glm::dot(wi, nl);
            if (cosL <= 0.0) continue;
            sum += gw[i] * gw[j] * test::pbrF(p, kUp, wo, wi).x * glm::dot(wi, kUp) * cosL / r2;
        }
    return Le * sum * area;
}

// Directional albedo at cos(theta_o): integral of f cos over the hemisphere, n x 2n
// Gauss-Legendre in (theta_i, phi), sin(theta_i) the Jacobian. f is isotropic, so wo lies
// in the xz plane of the normal's frame.
double hemisphereAlbedo(const test::PbrParams& p, double cosO, int n) {
    std::vector<double> tx, tw, px, pw;
    gaussLegendre(n, tx, tw);
    gaussLegendre(2 * n, px, pw);
    const dvec3 normal(0.0, 0.0, 1.0), wo(std::sqrt(std::max(0.0, 1.0 - cosO * cosO)), 0.0, cosO);
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double theta = 0.5 * M_PI * tx[i], c = std::cos(theta), s = std::sin(theta);
        for (int j = 0; j < 2 * n; ++j) {
            const double phi = 2.0 * M_PI * px[j];
            const dvec3 wi(s * std::cos(phi), s * std::sin(phi), c);
            sum += tw[i] * pw[j] * test::pbrF(p, normal, wo, wi).x * c * s;
        }
    }
    return 0.5 * M_PI * 2.0 * M_PI * sum;
}

// The albedo over the cos(theta_o) the top-down camera sees ([0.998, 1] here), tabulated
// and interpolated linearly: the albedo is smooth in cos(theta_o), and the table's spacing
// (2.5e-4) leaves an interpolation error of order 1e-8.
class AlbedoTable {
public:
    AlbedoTable(const test::PbrParams& p, double lo, int nodes) : m_lo(lo), m_step((1.0 - lo) / 8.0) {
        for (int k = 0; k <= 8; ++k) m_values[k] = hemisphereAlbedo(p, lo + k * m_step, nodes);
    }
    double operator()(double cosO) const {
        const double t = std::clamp((cosO - m_lo) / m_step, 0.0, 8.0);
        const int k = std::min(int(t), 7);
        return m_values[k] + (t - k) * (m_values[k + 1] - m_values[k]);
    }

private:
    double m_lo, m_step, m_values[9];
};

void expectBlockTest(const json& doc, const std::function<double(const Scene&, dvec3)>& radiance, int sub,
                     const std::string& name) {
    for (const std::string& strategy : kStrategies) {
        json d = doc;
        d["integrator"] = direct(strategy);
        Scene scene = test::sceneFromJson(d, name + "-" + strategy);
        Image image = test::renderScene(scene);
        std::vector<double> expected = test::expectedTopDown(
            scene, [&](dvec3 x) { return radiance(scene, x); }, sub);
        std::string report;
        int failures = test::blockTTest(image, expected, 8, kAlpha, int(kStrategies.size()), &report);
        EXPECT_EQ(failures, 0) << name << " under " << strategy << ": " << report;
        if (failures) writeExr(test::outputPath(name + "-" + strategy + ".exr"), image);
    }
}

}  // namespace

TEST(PbrClosedForm, PointLightEveryStrategy) {
    const double I = 10.0;
    const dvec3 light(0.0, 1.5, 0.0);
    const int spp = 64;
    for (const Surface& s : surfaces()) {
        json doc = planeScene(s.p, spp);
        doc["lights"].push_back(
            {{"type", "point"}, {"position", {light.x, light.y, light.z}}, {"intensity", {I, I, I}}});
        for (const std::string& strategy : kStrategies) {
            doc["integrator"] = direct(strategy);
            const std::string name = "pbr-point-" + s.name + "-" + strategy;
            Scene scene = test::sceneFromJson(doc, name);
            Image image = test::renderScene(scene);
            const dvec3 eye(scene.camera.eye);
            std::vector<double> jitter;
            std::vector<double> expected = test::expectedTopDown(
                scene,
                [&](dvec3 x) {
                    const dvec3 to = light - x;
                    const double d2 = glm::dot(to, to);
                    const dvec3 wi = to / std::sqrt(d2);
                    return test::pbrF(s.p, kUp, glm::normalize(eye - x), wi).x * I * wi.y / d2;
                },
                8, &jitter);
            // The spread over the pixel (exact variance), and float rounding: f to ~1e-5
            // (D's sensitivity to the half vector, 2 * 2.4e-7 / alpha, and ~20 roundings),
            // the sum of 64 samples to 64 * 2^-24.
            const double z = test::zScore(kAlpha, kSize * kSize * int(kStrategies.size()) * 2);
            int failures = 0;
            for (size_t p = 0; p < expected.size(); ++p) {
                const double tol = z * std::sqrt(jitter[p] / spp) + 2e-5 * expected[p] + 1e-6;
                if (std::abs(image.rgb[3 * p] - expected[p]) > tol) ++failures;
            }
            EXPECT_EQ(failures, 0) << name;
            if (failures) writeExr(test::outputPath(name + ".exr"), image);
        }
    }
}

TEST(PbrClosedForm, QuadLightEveryStrategy) {
    const double Le = 5.0;
    // Low and just outside the camera's view (it would hide the plane below it), beside a
    // patch [-1, 0.5] x [-0.75, 0.75] that sees it 10 to 75 degrees from the normal: the
    // specular lobe's flank and the diffuse term, with BRDF samples hitting it often enough
    // in every block for the t-test's variance estimate. u x v faces -y, toward the plane.
    const dvec3 origin(-1.7, 0.5, -0.75), u(0.6, 0.0, 0.0), v(0.0, 0.0, 1.5);
    const dvec3 eye(-0.25, 50.0, 0.0);
    for (Surface s : surfaces()) {
        // The metal at roughness 0.5 here: at 0.3 its lobe meets the light so rarely from the
        // far side of the patch that BRDF sampling hits it a few times per block, and the
        // block t-test's variance estimate is unreliable on such skewed pixel values.
        if (s.p.metallic == 1.0) s.p.roughness = 0.5;
        json doc = planeScene(s.p, 256);
        doc["camera"] = test::topDownCamera(eye.x, eye.z, 0.75);
        doc["shapes"].push_back({{"type", "quad"},
                                 {"origin", {origin.x, origin.y, origin.z}},
                                 {"edge_u", {u.x, u.y, u.z}},
                                 {"edge_v", {v.x, v.y, v.z}},
                                 {"emission", {Le, Le, Le}},
                                 {"material", "black"}});
        // The reference converged: 32 and 64 nodes a side agree to 1e-4 relative near the
        // light and far from it, far below a block mean's Monte Carlo error (~1e-2).
        for (dvec3 x : {dvec3(-0.95, 0.0, 0.0), dvec3(0.4, 0.0, 0.2), dvec3(0.45, 0.0, -0.7)}) {
            const double a = quadRadiance(s.p, eye, x, origin, u, v, Le, 32);
            const double b = quadRadiance(s.p, eye, x, origin, u, v, Le, 64);
            ASSERT_NEAR(a, b, 1e-4 * b) << s.name << " at x = " << x.x << ", " << x.z;
        }
        expectBlockTest(
            doc,
            [&](const Scene& scene, dvec3 x) {
                return quadRadiance(s.p, dvec3(scene.camera.eye), x, origin, u, v, Le, 32);
            },
            4, "pbr-quad-" + s.name);
    }
}

TEST(PbrClosedForm, ConstantEnvironmentEveryStrategy) {
    const double Le = 1.0;
    for (const Surface& s : surfaces()) {
        json doc = planeScene(s.p, 128);
        doc["lights"].push_back({{"type", "environment"}, {"radiance", {Le, Le, Le}}});
        // The reference converged: 128 and 256 nodes agree to 1e-5 (a block mean's Monte
        // Carlo error is ~1e-3 here).
        ASSERT_NEAR(hemisphereAlbedo(s.p, 0.999, 128), hemisphereAlbedo(s.p, 0.999, 256), 1e-5) << s.name;
        const AlbedoTable albedo(s.p, 0.998, 128);
        expectBlockTest(
            doc,
            [&](const Scene& scene, dvec3 x) { return Le * albedo(glm::normalize(dvec3(scene.camera.eye) - x).y); }, 1,
            "pbr-environment-" + s.name);
    }
}
