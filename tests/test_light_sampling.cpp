// sampleLight and lightPdf of shaders/lights/lights.glsl, run as GLSL on lavapipe
// (shaders/tests/light_sampling.comp): the directions each light's sampler draws pass a
// chi-square test against the pdf the integrator would evaluate for them (trace, then
// lightPdf at the first hit), every sample's own pdf equals that traced pdf, the pdf
// integrates to the mass the sampler does not decline, and delta lights return exactly
// what SCENE_FORMAT.md promises. The harness must reject deliberately wrong pdfs.
//
// Where samples are histogrammed. Area lights are tested in a chart of the light's own
// surface: the sampled direction is mapped (ray from x, in double) to the point it hits,
// given chart coordinates in [0,1]^2, and the GPU's solid-angle pdf is turned into a density
// in the chart with the exact Jacobian d(omega)/dA = cos(theta_y) / d^2 times dA/(ds dt).
// The chart puts the light's outline on cell edges (a quad's edges in direction space are
// not rows of the sphere histogram) and removes the 1/cos(theta_y) singularity that the
// area and cap strategies have in direction space at the sphere's silhouette, which the
// Gauss-Legendre cells could not integrate. Uniform-in-cone (sphere solid_angle) and the
// environment are tested on the direction sphere itself, the cone with the zoomed cap.
//
// Expected integrals of the pdf over all directions (mass the sampler does not decline):
//   quad, mesh (every triangle facing x), two-sided lights, solid_angle, cap, environment: 1
//   sphere `area`: uniform on the whole sphere, declined on the hidden part; the visible cap
//     from distance D is {cos(alpha) > r/D}, of area 2 pi r^2 (1 - r/D): (1 - r/D) / 2
//   one-sided mesh with triangle k facing away: 1 - A_k / A
//
// Significance: alpha = 0.01 for the file, Sidak-corrected over kChi2Tests tests; fixed seeds.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "chi2.h"
#include "light_kernel.h"
#include "render/scene_arrays.h"
#include "test_frame.h"

using namespace penumbra;
using glm::dvec2;
using glm::dvec3;
using glm::vec3;
using gpu::LightTestRecord;

namespace {

constexpr double kAlpha = 0.01;
// Chi-square tests in this file that must pass: quad 4 points + 1 two-sided from behind,
// sphere 3 strategies x 3 distances, mesh 2 charts + 2 triangle frequencies, environment 2.
constexpr int kChi2Tests = 20;
constexpr uint32_t kSamples = 1u << 20;  // >= 10^6 per test
constexpr double kPi = std::numbers::pi;
constexpr int kChartRes = 64;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Relative agreement of sampleLight's pdf with lightPdf at the traced hit.
constexpr double kConsistency = 1e-3;

bool accepted(const LightTestRecord& r) { return (r.flags & gpu::LIGHT_TEST_ACCEPTED) != 0u; }

// ---- Scenes ----------------------------------------------------------------------------------

Scene sceneWithShape(const Shape& shape) {
    Scene scene;
    scene.materials.push_back(Material{});
    scene.shapes.push_back(shape);
    return scene;
}

Shape quadShape(vec3 origin, vec3 edgeU, vec3 edgeV, bool twoSided) {
    Shape s;
    s.type = ShapeType::Quad;
    s.origin = origin;
    s.edgeU = edgeU;
    s.edgeV = edgeV;
    s.emission = vec3(1.0f, 2.0f, 3.0f);
    s.twoSided = twoSided;
    return s;
}

Shape sphereShape(vec3 center, float radius) {
    Shape s;
    s.type = ShapeType::Sphere;
    s.center = center;
    s.radius = radius;
    s.emission = vec3(4.0f);
    return s;
}

// ---- Charts of area lights --------------------------------------------------------------------

// Where a ray from x hits the light, in chart coordinates, with what the Jacobian needs.
struct Located {
    dvec2 st;            // chart coordinates (may stray outside [0,1]^2 by rounding)
    double areaPerChart; // dA / (ds dt) at the point
    double cosY;         // |cos| between the ray and the surface normal there
    double dist;         // distance from x
    int part;            // mesh: triangle (input order); else 0
};

class LightChart {
public:
    virtual ~LightChart() = default;
    // First intersection of x + t wi (t > 0) with the light's surface, either side.
    virtual std::optional<Located> locate(dvec3 x, dvec3 wi) const = 0;
    // The same for the point x + t wi that a traced ray found (t from the GPU). Near a
    // sphere's silhouette the hit of a float ray is ill-conditioned (the discriminant is
    // the difference of nearly equal squares): the Jacobian must then be taken where the
    // GPU's lightPdf was, not where the exact ray meets the sphere.
    virtual std::optional<Located> locateAt(dvec3 x, dvec3 wi, double /*t*/) const { return locate(x, wi); }
    // The surface point at chart coordinates st.
    virtual dvec3 point(dvec2 st) const = 0;
};

// A quad's own parameters: y = origin + s edgeU + t edgeV; dA = |edgeU x edgeV| ds dt.
class QuadChart : public LightChart {
public:
    QuadChart(dvec3 origin, dvec3 u, dvec3 v) : m_o(origin), m_u(u), m_v(v), m_n(glm::cross(u, v)) {}
    std::optional<Located> locate(dvec3 x, dvec3 wi) const override {
        const double denom = glm::dot(m_n, wi);
        if (denom == 0.0) return std::nullopt;
        const double t = glm::dot(m_n, m_o - x) / denom;
        if (!(t > 0.0)) return std::nullopt;
        const dvec3 local = x + t * wi - m_o;
        const dvec3 w = m_n / glm::dot(m_n, m_n);
        return Located{{glm::dot(w, glm::cross(local, m_v)), glm::dot(w, glm::cross(m_u, local))},
                       glm::length(m_n), std::abs(denom) / glm::length(m_n), t, 0};
    }
    dvec3 point(dvec2 st) const override { return m_o + st.x * m_u + st.y * m_v; }

private:
    dvec3 m_o, m_u, m_v, m_n;
};

// The cap of a sphere visible from x: s = (1 - cos(alpha)) / (1 - r/D), alpha the angle of
// the surface normal from the axis toward x, t = azimuth / 2 pi; uniform area on the cap is
// uniform in (s, t), dA = 2 pi r^2 (1 - r/D) ds dt.
class SphereCapChart : public LightChart {
public:
    SphereCapChart(dvec3 center, double r, dvec3 x)
        : m_c(center), m_r(r), m_D(glm::length(x - center)), m_frame(x - center) {}
    double capHeight() const { return 1.0 - m_r / m_D; }
    std::optional<Located> locate(dvec3 x, dvec3 wi) const override {
        // Nearest root of |x + t wi - c| = r; a float ray that passes the silhouette by less
        // than 1e-6 (|x| + |c| + D) (its rounding; see SphereConditioning) takes the tangent point.
        const dvec3 f = x - m_c;
        const double b = -glm::dot(f, wi);
        const dvec3 l = f + b * wi;
        const double disc = m_r * m_r - glm::dot(l, l);
        const double slack = 1e-6 * (glm::length(x) + glm::length(m_c) + m_D);
        if (disc < -2.0 * m_r * slack) return std::nullopt;
        const double t = b - std::sqrt(std::max(0.0, disc));
        if (!(t > 0.0)) return std::nullopt;
        return locateAt(x, wi, t);
    }
    std::optional<Located> locateAt(dvec3 x, dvec3 wi, double t) const override {
        // As surfaceAt in surface.glsl: the normal of the point the ray reached, on the sphere.
        const dvec3 ny = glm::normalize(x + t * wi - m_c);
        const dvec3 local = m_frame.toLocal(ny);
        double phi = std::atan2(local.y, local.x);
        if (phi < 0.0) phi += 2.0 * kPi;
        return Located{{(1.0 - local.z) / capHeight(), phi / (2.0 * kPi)},
                       2.0 * kPi * m_r * m_r * capHeight(), std::max(0.0, -glm::dot(wi, ny)), t, 0};
    }
    dvec3 point(dvec2 st) const override {
        const double oneMinusCos = st.x * capHeight();
        const double sinA = std::sqrt(std::max(0.0, oneMinusCos * (2.0 - oneMinusCos)));
        const double phi = 2.0 * kPi * st.y;
        return m_c + m_r * m_frame.toWorld({sinA * std::cos(phi), sinA * std::sin(phi), 1.0 - oneMinusCos});
    }

private:
    dvec3 m_c;
    double m_r, m_D;
    test::Frame m_frame;
};

// K triangles side by side: s in [k/K, (k+1)/K) is triangle k, with s' = K s - k and
// barycentrics (b0, b1, b2) = (s' (1 - t), s' t, 1 - s') as in the warp test, so
// dA = 2 A_k s' ds' dt = 2 A_k K s' ds dt.
class MeshChart : public LightChart {
public:
    explicit MeshChart(std::vector<std::array<dvec3, 3>> triangles) : m_tri(std::move(triangles)) {}
    int parts() const { return int(m_tri.size()); }
    double area(int k) const {
        return 0.5 * glm::length(glm::cross(m_tri[k][1] - m_tri[k][0], m_tri[k][2] - m_tri[k][0]));
    }
    std::optional<Located> locate(dvec3 x, dvec3 wi) const override {
        // The triangle whose plane the ray crosses (t > 0) most inside it; the test meshes
        // do not overlap as seen from x, so inside means hit, and a ray through an edge goes
        // to either neighbour.
        std::optional<Located> best;
        double bestInside = -std::numeric_limits<double>::infinity();
        const double K = double(m_tri.size());
        for (int k = 0; k < parts(); ++k) {
            const auto& p = m_tri[k];
            const dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
            const double denom = glm::dot(n, wi);
            if (denom == 0.0) continue;
            const double t = glm::dot(n, p[0] - x) / denom;
            if (!(t > 0.0)) continue;
            const dvec3 y = x + t * wi;
            const double nn = glm::dot(n, n);
            const double b1 = glm::dot(glm::cross(y - p[0], p[2] - p[0]), n) / nn;  // weight of p1
            const double b2 = glm::dot(glm::cross(p[1] - p[0], y - p[0]), n) / nn;  // weight of p2
            const double b0 = 1.0 - b1 - b2;
            const double inside = std::min({b0, b1, b2});
            if (inside <= bestInside) continue;
            bestInside = inside;
            const double sp = std::clamp(b0 + b1, 0.0, 1.0);
            const double tt = sp > 0.0 ? std::clamp(b1 / (b0 + b1), 0.0, 1.0) : 0.0;
            best = Located{{(k + sp) / K, tt}, 2.0 * area(k) * K * sp, std::abs(denom) / std::sqrt(nn), t, k};
        }
        return best;
    }
    dvec3 point(dvec2 st) const override {
        const double K = double(m_tri.size());
        const int k = std::min(int(st.x * K), parts() - 1);
        const double sp = st.x * K - k;
        const double b0 = sp * (1.0 - st.y), b1 = sp * st.y, b2 = 1.0 - sp;
        return b0 * m_tri[k][0] + b1 * m_tri[k][1] + b2 * m_tri[k][2];
    }

private:
    std::vector<std::array<dvec3, 3>> m_tri;
};

// ---- The checks --------------------------------------------------------------------------------

struct LightCase {
    std::string name;
    uint32_t light = 0;
    vec3 x{0.0f};
    vec3 n{0.0f, 0.0f, 1.0f};
    uint32_t sphereSampling = gpu::SPHERE_SOLID_ANGLE;
    double expectedIntegral = 1.0;
};

// The consistency check: each accepted sample's pdf equals lightPdf at the traced first hit
// to kConsistency, and its distance lets the integrator's shadow ray (which stops at
// dist (1 - 1e-4), direct.comp) end before the traced hit on the light, unless the float
// conditioning of the geometry at that sample allows more: `allowance(record)` gives the
// extra relative error of each (0 where the geometry is well conditioned, infinity where
// the traced ray may miss the light by rounding). Samples that need the allowance are
// counted; there may be at most `maxConditionedFraction` of them.
struct Allowance {
    double pdf = 0.0, distance = 0.0;
};
constexpr Allowance kAnything{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};

struct Consistency {
    size_t accepted = 0, conditioned = 0;
};

Consistency checkConsistency(const std::string& name, const std::vector<LightTestRecord>& samples,
                             const std::function<Allowance(const LightTestRecord&)>& allowance,
                             double maxConditionedFraction) {
    Consistency c;
    size_t reported = 0;
    for (size_t i = 0; i < samples.size(); ++i) {
        const LightTestRecord& r = samples[i];
        if (!accepted(r)) continue;
        ++c.accepted;
        const bool hit = (r.flags & gpu::LIGHT_TEST_HIT_LIGHT) != 0u;
        const double error = hit ? std::abs(double(r.tracedPdf) - r.pdf) / r.pdf
                                 : std::numeric_limits<double>::infinity();
        // How far the sample's distance overshoots the shadow ray's end, relative.
        // (At infinity, the environment, the shadow ray has no end.)
        const bool finite = r.dist < std::numeric_limits<float>::max();
        const double overshoot = hit && finite ? (double(r.dist) * (1.0 - 1e-4) - double(r.tracedT)) / r.dist : 0.0;
        if (error <= kConsistency && overshoot <= 0.0) continue;
        const Allowance allowed = allowance(r);
        if (error <= kConsistency + allowed.pdf && overshoot <= allowed.distance) {
            ++c.conditioned;
        } else if (reported++ < 5) {
            ADD_FAILURE() << name << ": sample " << i << " wi = (" << r.wi.x << ", " << r.wi.y << ", " << r.wi.z
                          << ") has pdf " << r.pdf << " and distance " << r.dist << " but lightPdf at the traced hit is "
                          << r.tracedPdf << " at distance " << r.tracedT << (hit ? "" : " (the traced ray missed the light)")
                          << "; conditioning allows relative " << kConsistency + allowed.pdf << " and "
                          << allowed.distance;
        }
    }
    EXPECT_EQ(reported, 0u) << name << ": samples whose pdf or distance disagree with the traced hit";
    EXPECT_LE(double(c.conditioned), maxConditionedFraction * double(samples.size()))
        << name << ": more ill-conditioned samples than their geometry explains";
    std::printf("[ %s ] consistency: %zu accepted, %zu outside 1e-3 but within their float conditioning "
                "(bound %.3g of the samples)\n",
                name.c_str(), c.accepted, c.conditioned, maxConditionedFraction);
    return c;
}

test::SquareChi2Options chartOptions(const std::string& dump, double evaluationTolerance) {
    return {kChartRes, kAlpha, kChi2Tests, "chi2_light_" + dump, evaluationTolerance};
}

// Histogram of the samples in the chart, and the GPU pdf (times `scale`, a test-of-the-test
// hook) as a density in the chart.
test::Chi2Result chartChi2(test::LightKernel& kernel, const LightCase& c, const LightChart& chart,
                           const std::vector<LightTestRecord>& samples, uint32_t pdfSphereSampling,
                           const std::string& dump, double evaluationTolerance = 0.0,
                           const std::function<double(const Located&)>& scale = {}) {
    const dvec3 x(c.x);
    std::vector<dvec2> points(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
        const LightTestRecord& r = samples[i];
        if (!accepted(r)) {
            points[i] = {kNaN, kNaN};
            continue;
        }
        const auto at = chart.locate(x, glm::normalize(dvec3(r.wi)));
        // A sample that hits no part of the light lies outside the chart: the harness fails it.
        points[i] = at ? at->st : dvec2(-1.0, -1.0);
        // Rounding of the float direction moves the point by < 1e-3 of the chart near a
        // silhouette (see the sphere tests); keep such samples in the chart.
        const dvec2 st = points[i];
        if (at && st.x >= -1e-3 && st.y >= -1e-3 && st.x <= 1.0 + 1e-3 && st.y <= 1.0 + 1e-3)
            points[i] = glm::clamp(st, dvec2(0.0), dvec2(1.0));
    }
    auto pdf = [&](const std::vector<dvec2>& st) {
        std::vector<vec3> dirs(st.size());
        for (size_t i = 0; i < st.size(); ++i) dirs[i] = vec3(glm::normalize(chart.point(st[i]) - x));
        std::vector<float> hitT;
        std::vector<double> values = kernel.pdf(c.light, c.x, c.n, pdfSphereSampling, dirs, &hitT);
        for (size_t i = 0; i < st.size(); ++i) {
            if (values[i] == 0.0) continue;
            // The Jacobian at the hit the GPU evaluated lightPdf at.
            const auto at = chart.locateAt(x, glm::normalize(dvec3(dirs[i])), hitT[i]);
            if (!at) {
                values[i] = 0.0;
                continue;
            }
            values[i] *= at->cosY / (at->dist * at->dist) * at->areaPerChart * (scale ? scale(*at) : 1.0);
        }
        return values;
    };
    return test::chi2TestSquare(points, pdf, chartOptions(dump, evaluationTolerance));
}

// Bound on how many of n samples fall in a band of probability p: 5 binomial sigmas more.
double bandBound(double p, double n) { return p + 5.0 * std::sqrt(p / n) + 10.0 / n; }

size_t countDeclined(const std::vector<LightTestRecord>& samples) {
    return size_t(std::count_if(samples.begin(), samples.end(), [](const auto& r) { return !accepted(r); }));
}

// Chi-square, integral and declined fraction of one area light seen from one point.
void checkChart(test::LightKernel& kernel, const LightCase& c, const LightChart& chart,
                const std::vector<LightTestRecord>& samples, double evaluationTolerance = 0.0) {
    const auto r = chartChi2(kernel, c, chart, samples, c.sphereSampling, c.name, evaluationTolerance);
    EXPECT_TRUE(r.passed) << c.name << ": " << r.message;
    EXPECT_NEAR(r.pdfIntegral, c.expectedIntegral, r.integralTolerance) << c.name << ": " << r.message;
    // The declined fraction is binomial with mean 1 - integral: 5 sigma (+ the integral's
    // tolerance) is far beyond what chance produces (the chi2 above tests it too).
    const double p = 1.0 - c.expectedIntegral, n = double(samples.size());
    EXPECT_NEAR(double(countDeclined(samples)) / n, p, 5.0 * std::sqrt(p * (1.0 - p) / n) + r.integralTolerance)
        << c.name;
    std::printf("[ %s ] declined %.6f (expected %.6f); %s\n", c.name.c_str(), double(countDeclined(samples)) / n, p,
                r.message.c_str());
}

}  // namespace

// ---- Quad light ----------------------------------------------------------------------------------

namespace {

// A tilted 1 x 1.1 quad; its front normal is normalize(edgeU x edgeV).
const vec3 kQuadOrigin(0.2f, 1.0f, -0.3f), kQuadU(0.0f, 0.3f, 1.0f), kQuadV(1.1f, 0.2f, 0.0f);

vec3 quadCenter() { return kQuadOrigin + 0.5f * kQuadU + 0.5f * kQuadV; }
vec3 quadNormal() { return glm::normalize(glm::cross(kQuadU, kQuadV)); }

// A sample whose point lies within 1e-5 of the quad's edge (in chart units) can trace past
// it: float rounding of y and wi (~1e-7 relative) decides there. Elsewhere no allowance.
std::function<Allowance(const LightTestRecord&)> nearChartEdge(const LightChart& chart, vec3 x) {
    return [&chart, x](const LightTestRecord& r) {
        const auto at = chart.locate(dvec3(x), glm::normalize(dvec3(r.wi)));
        if (!at) return Allowance{};
        const dvec2 st = at->st;
        return std::min({st.x, st.y, 1.0 - st.x, 1.0 - st.y}) < 1e-5 ? kAnything : Allowance{};
    };
}

}  // namespace

TEST(LightSampling, QuadFromSeveralPoints) {
    const QuadChart chart(kQuadOrigin, kQuadU, kQuadV);
    const vec3 c = quadCenter(), n = quadNormal(), side = glm::normalize(kQuadU);
    struct Point {
        std::string name;
        vec3 x;
    };
    const Point points[] = {
        {"quad_close", c + 0.05f * n},                      // the quad fills most of the hemisphere
        {"quad_far", c + 6.0f * n + 2.0f * side},           // small and off-axis
        {"quad_grazing", c + 2.0f * side + 0.03f * n},      // 1 degree above the quad's plane
        {"quad_corner", kQuadOrigin + 0.01f * n + 0.002f * side},  // just above a corner
    };
    auto arrays = buildSceneArrays(sceneWithShape(quadShape(kQuadOrigin, kQuadU, kQuadV, false)));
    test::LightKernel kernel(arrays);
    uint32_t seed = 100;
    for (const Point& p : points) {
        SCOPED_TRACE(p.name);
        LightCase lc{p.name, 0, p.x};
        const auto samples = kernel.sample(0, p.x, n, gpu::SPHERE_SOLID_ANGLE, seed++, kSamples);
        // The band within 1e-5 of an edge holds 4e-5 of the uniform chart density.
        checkConsistency(p.name, samples, nearChartEdge(chart, p.x), bandBound(4e-5, kSamples));
        checkChart(kernel, lc, chart, samples);
    }
}

TEST(LightSampling, QuadFromBehind) {
    // One-sided: every sample is declined and the pdf, as the integrator evaluates it after
    // a ray hits the back, is 0 (sampleLight never produces those directions).
    const QuadChart chart(kQuadOrigin, kQuadU, kQuadV);
    const vec3 x = quadCenter() - 0.7f * quadNormal();
    {
        auto arrays = buildSceneArrays(sceneWithShape(quadShape(kQuadOrigin, kQuadU, kQuadV, false)));
        test::LightKernel kernel(arrays);
        const auto samples = kernel.sample(0, x, vec3(0, 0, 1), gpu::SPHERE_SOLID_ANGLE, 110, 1u << 16);
        EXPECT_EQ(countDeclined(samples), samples.size());
        std::vector<vec3> dirs;
        for (int i = 0; i < 32; ++i)
            for (int j = 0; j < 32; ++j)
                dirs.push_back(vec3(glm::normalize(chart.point({(i + 0.5) / 32, (j + 0.5) / 32}) - dvec3(x))));
        const auto pdf = kernel.pdf(0, x, vec3(0, 0, 1), gpu::SPHERE_SOLID_ANGLE, dirs);
        size_t nonZero = size_t(std::count_if(pdf.begin(), pdf.end(), [](double v) { return v != 0.0; }));
        EXPECT_EQ(nonZero, 0u) << "lightPdf must be 0 for the back of a one-sided quad";
    }
    {
        // Two-sided: the back emits, everything is sampled.
        auto arrays = buildSceneArrays(sceneWithShape(quadShape(kQuadOrigin, kQuadU, kQuadV, true)));
        test::LightKernel kernel(arrays);
        LightCase lc{"quad_two_sided_behind", 0, x};
        const auto samples = kernel.sample(0, x, vec3(0, 0, 1), gpu::SPHERE_SOLID_ANGLE, 111, kSamples);
        checkConsistency(lc.name, samples, nearChartEdge(chart, x), bandBound(4e-5, kSamples));
        checkChart(kernel, lc, chart, samples);
    }
}

// ---- Sphere light ----------------------------------------------------------------------------------

namespace {

struct SphereSetup {
    std::string name;
    vec3 center;
    float radius;
    vec3 x;
};

// Close (D = 1.05 r) and moderate (D = 4 r) along a tilted axis, so sampling frames are
// general; very distant (r / D = 1e-3) along -x, where the sampling frame is a signed
// permutation of the world axes and the GPU's directions are exact in the histogram's frame:
// the cone is 1 - cos(thetaMax) = 5e-7 wide, and 1e-7 of rotation rounding at its rim would
// be 20% of a row.
std::vector<SphereSetup> sphereSetups() {
    const vec3 c(0.3f, -0.2f, 0.5f), axis(0.36f, 0.48f, 0.8f);
    const float r = 0.7f;
    return {{"d1.05r", c, r, c + 1.05f * r * axis},
            {"d4r", c, r, c + 4.0f * r * axis},
            {"d1000r", vec3(0.0f), 0.01f, vec3(10.0f, 0.0f, 0.0f)}};
}

// 1 - cos(thetaMax) of the cone the sphere subtends, as sphereCone in lights.glsl forms it
// in float, so the cone's edge falls on a row edge of the histogram.
double gpuConeOneMinusCos(const SphereSetup& s) {
    const float D = glm::length(s.x - s.center);
    const float sin2 = (s.radius / D) * (s.radius / D);
    const float cosMax = std::sqrt(std::max(0.0f, 1.0f - sin2));
    return double(sin2 / (1.0f + cosMax));
}

const char* strategyName(uint32_t s) {
    return s == gpu::SPHERE_AREA ? "area" : s == gpu::SPHERE_CAP ? "cap" : "solid_angle";
}

// Float conditioning near the silhouette. A traced hit x + t wi is formed in float from
// coordinates of size |x| + d, the sampled point c + r n_y from |c| + r: each is off by
// dp ~ 4 * 2^-24 (|x| + |c| + d + r) (a product, a sum and the root's own rounding), and
// a normal taken there by dp / r. That changes cos(theta_y), hence the area and cap pdfs
// d^2 / (cos A), by dp / (r cos) relative where the GPU's own lightPdf is evaluated, and by
// dp / (r cos^2) between a sampled point and the traced hit of the float direction toward it
// (the ray passes the point at dp, which moves the hit by dp / cos along the surface and by
// dp tan(theta_y) <= dp / cos along the ray: relative dp / (d cos) on the distance; the
// solid_angle strategy's closed-form distance has the same conditioning at the silhouette,
// where its square root of r^2 cos^2 is taken). Where r^2 cos^2, the discriminant, is within
// its rounding 2 r dp, the traced ray may miss the sphere altogether.
struct SphereConditioning {
    double dp, r;
    Allowance allowance(double cosY, double d) const {
        if (cosY * cosY <= 2.0 * dp / r) return kAnything;
        return {dp / (r * cosY * cosY), dp / (d * cosY)};
    }
    double pdfError(double cosY) const { return cosY * cosY <= 2.0 * dp / r ? 1.0 : std::min(1.0, dp / (r * cosY)); }
};

SphereConditioning sphereConditioning(const SphereSetup& s) {
    const dvec3 x(s.x), c(s.center);
    const double d = glm::length(x - c);
    return {4.0 * std::ldexp(1.0, -24) * (glm::length(x) + glm::length(c) + d + s.radius), s.radius};
}

// Integral over the visible cap, in the cap chart, of strategy's sampling density (relative
// to all samples) times f(cos(theta_y)); the densities depend on s alone. Gives the
// probability of the ill-conditioned band and the float error bound of the pdf's integral.
double sphereChartIntegral(const SphereSetup& s, const SphereCapChart& chart, uint32_t strategy,
                           const std::function<double(double)>& f) {
    const dvec3 x(s.x), c(s.center);
    const double r = s.radius, D = glm::length(x - c);
    const double cone = 2.0 * kPi * gpuConeOneMinusCos(s);
    const int steps = 200000;
    double sum = 0.0;
    for (int i = 0; i < steps; ++i) {
        const dvec3 y = chart.point({(i + 0.5) / steps, 0.0});
        const double d = glm::length(y - x);
        const double cosY = glm::dot(glm::normalize(x - y), glm::normalize(y - c));
        double density = 1.0;  // cap: uniform in s
        if (strategy == gpu::SPHERE_AREA) density = 0.5 * (1.0 - r / D);
        if (strategy == gpu::SPHERE_SOLID_ANGLE) density = cosY / (d * d) * 2.0 * kPi * r * r * (1.0 - r / D) / cone;
        sum += density * f(cosY) / steps;
    }
    return sum;
}

}  // namespace

TEST(LightSampling, SphereAreaCapAndSolidAngle) {
    uint32_t seed = 200;
    for (const SphereSetup& s : sphereSetups()) {
        auto arrays = buildSceneArrays(sceneWithShape(sphereShape(s.center, s.radius)));
        test::LightKernel kernel(arrays);
        const SphereCapChart chart(s.center, s.radius, s.x);
        const double D = glm::length(dvec3(s.x) - dvec3(s.center)), r = s.radius;
        for (uint32_t strategy : {gpu::SPHERE_AREA, gpu::SPHERE_CAP, gpu::SPHERE_SOLID_ANGLE}) {
            const std::string name = std::string("sphere_") + strategyName(strategy) + "_" + s.name;
            SCOPED_TRACE(name);
            LightCase lc{name, 0, s.x, vec3(0, 0, 1), strategy,
                         strategy == gpu::SPHERE_AREA ? 0.5 * (1.0 - r / D) : 1.0};
            const auto samples = kernel.sample(0, s.x, lc.n, strategy, seed++, kSamples);

            const SphereConditioning cond = sphereConditioning(s);
            // Samples that may need the allowance: those where it exceeds kConsistency.
            const double band = sphereChartIntegral(s, chart, strategy, [&](double cosY) {
                return cond.allowance(cosY, 1.0).pdf > kConsistency ? 1.0 : 0.0;
            });
            // The pdf's integral: relative error dp / (r cos) where it is evaluated, or all of
            // it lost where the traced ray may miss.
            const double evaluation = sphereChartIntegral(s, chart, strategy, [&](double cosY) {
                return cond.pdfError(cosY);
            });
            checkConsistency(
                name, samples,
                [&](const LightTestRecord& rec) {
                    const auto at = chart.locate(dvec3(s.x), glm::normalize(dvec3(rec.wi)));
                    return at ? cond.allowance(at->cosY, at->dist) : Allowance{};
                },
                bandBound(band, double(samples.size())));

            if (strategy != gpu::SPHERE_SOLID_ANGLE) {
                checkChart(kernel, lc, chart, samples, evaluation);
                continue;
            }
            // Uniform in the cone about the direction to the centre: the direction sphere,
            // zoomed on the cone, in the frame about that direction.
            const test::Frame frame(dvec3(s.center) - dvec3(s.x));
            std::vector<vec3> local(samples.size());
            for (size_t i = 0; i < samples.size(); ++i)
                local[i] = accepted(samples[i]) ? vec3(frame.toLocal(dvec3(samples[i].wi))) : vec3(0.0f);
            test::SphereChi2Options options;
            options.capOneMinusCos = gpuConeOneMinusCos(s);
            options.significance = kAlpha;
            options.numTests = kChi2Tests;
            options.dumpName = "chi2_light_" + name;
            options.evaluationTolerance = evaluation;
            const auto result = test::chi2TestSphere(
                local,
                [&](const std::vector<vec3>& dirs) {
                    std::vector<vec3> world(dirs.size());
                    for (size_t i = 0; i < dirs.size(); ++i) world[i] = vec3(frame.toWorld(dvec3(dirs[i])));
                    return kernel.pdf(0, s.x, lc.n, strategy, world);
                },
                options);
            EXPECT_TRUE(result.passed) << name << ": " << result.message;
            EXPECT_NEAR(result.pdfIntegral, 1.0, result.integralTolerance) << name << ": " << result.message;
            EXPECT_EQ(countDeclined(samples), 0u) << name;
            std::printf("[ %s ] %s\n", name.c_str(), result.message.c_str());
        }
    }
}

// ---- Mesh light ------------------------------------------------------------------------------------

namespace {

// Four equilateral triangles seen from the origin in different directions, none hiding
// another, with areas 1.3, 0.117, 0.013 and 0.0012 (circumradius R: 3 sqrt(3) / 4 R^2): a
// selection that ignored the alias table's area weights would be off by up to 250x.
struct MeshSetup {
    std::vector<std::array<dvec3, 3>> triangles;
    Shape shape;
};

MeshSetup meshSetup(bool flipSecond, bool twoSided) {
    struct Spec {
        dvec3 centre;
        double R;
        dvec3 tilt;
    };
    const Spec specs[] = {{{0.0, 0.0, 2.5}, 1.0, {0.2, -0.1, 0.0}},
                          {{2.0, 0.5, 0.0}, 0.3, {0.0, 0.3, 0.2}},
                          {{-1.5, 1.0, 1.0}, 0.1, {0.1, 0.1, -0.3}},
                          {{0.0, -2.0, 0.5}, 0.03, {-0.2, 0.0, 0.1}}};
    MeshSetup m;
    m.shape.type = ShapeType::Mesh;
    m.shape.emission = vec3(0.5f, 1.0f, 2.0f);
    m.shape.twoSided = twoSided;
    for (size_t k = 0; k < std::size(specs); ++k) {
        const Spec& sp = specs[k];
        // Front normal toward the origin, tilted; counter-clockwise about it is the front.
        const dvec3 n = glm::normalize(glm::normalize(-sp.centre) + sp.tilt);
        const test::Frame f(n);
        std::array<dvec3, 3> p;
        for (int j = 0; j < 3; ++j) {
            const double a = 2.0 * kPi * j / 3.0;
            // Vertices in float, as the GPU holds them: the chart uses exactly those.
            p[j] = dvec3(vec3(sp.centre + sp.R * (std::cos(a) * f.t + std::sin(a) * f.b)));
        }
        if (glm::dot(glm::cross(p[1] - p[0], p[2] - p[0]), n) < 0.0) std::swap(p[1], p[2]);
        if (flipSecond && k == 1) std::swap(p[1], p[2]);  // faces away from the origin
        m.triangles.push_back(p);
        for (int j = 0; j < 3; ++j) {
            m.shape.indices.push_back(uint32_t(m.shape.positions.size()));
            m.shape.positions.push_back(vec3(p[j]));
        }
    }
    return m;
}

// Within 1e-5 (barycentric) of a triangle's edge the traced ray may pass the edge by
// rounding; that band is ~6e-5 of the uniform chart density.
std::function<Allowance(const LightTestRecord&)> nearTriangleEdge(const MeshChart& chart) {
    return [&chart](const LightTestRecord& r) {
        const auto at = chart.locate(dvec3(0.0), glm::normalize(dvec3(r.wi)));
        if (!at) return Allowance{};
        const double sp = at->st.x * chart.parts() - at->part, t = at->st.y;
        return std::min({sp * (1.0 - t), sp * t, 1.0 - sp}) < 1e-5 ? kAnything : Allowance{};
    };
}

}  // namespace

TEST(LightSampling, MeshTrianglesOfVeryDifferentAreas) {
    uint32_t seed = 300;
    for (bool twoSided : {false, true}) {
        const std::string name = twoSided ? "mesh_two_sided" : "mesh_one_sided";
        SCOPED_TRACE(name);
        const MeshSetup m = meshSetup(true, twoSided);
        const MeshChart chart(m.triangles);
        auto arrays = buildSceneArrays(sceneWithShape(m.shape));
        test::LightKernel kernel(arrays);
        double total = 0.0;
        std::vector<double> probability;
        for (int k = 0; k < chart.parts(); ++k) total += chart.area(k);
        for (int k = 0; k < chart.parts(); ++k)
            probability.push_back(!twoSided && k == 1 ? 0.0 : chart.area(k) / total);
        // One-sided: the second triangle faces away, its samples are declined.
        LightCase lc{name, 0, vec3(0.0f), vec3(0, 0, 1), gpu::SPHERE_SOLID_ANGLE,
                     twoSided ? 1.0 : 1.0 - chart.area(1) / total};
        const auto samples = kernel.sample(0, lc.x, lc.n, lc.sphereSampling, seed++, kSamples);
        checkConsistency(name, samples, nearTriangleEdge(chart), bandBound(6e-5, kSamples));
        checkChart(kernel, lc, chart, samples);

        // Which triangle each sample came from, against A_k / A (the alias table's job).
        std::vector<double> counts(chart.parts(), 0.0);
        size_t declined = 0;
        for (const auto& r : samples) {
            if (!accepted(r)) {
                ++declined;
                continue;
            }
            const auto at = chart.locate(dvec3(0.0), glm::normalize(dvec3(r.wi)));
            ASSERT_TRUE(at.has_value());
            counts[at->part] += 1.0;
        }
        std::vector<double> expected = probability;
        if (!twoSided) {
            expected.erase(expected.begin() + 1);
            EXPECT_EQ(counts[1], 0.0);
            counts.erase(counts.begin() + 1);
        }
        const auto r = test::chi2TestDiscrete(counts, expected, declined,
                                              {kAlpha, kChi2Tests, "chi2_light_" + name + "_triangles"});
        EXPECT_TRUE(r.passed) << name << " triangle choice: " << r.message;
        std::printf("[ %s triangles ] %.0f %.0f %.0f (declined %zu) of %u; %s\n", name.c_str(), counts[0], counts[1],
                    counts[2], declined, kSamples, r.message.c_str());
    }
}

// ---- Environment ------------------------------------------------------------------------------------

TEST(LightSampling, EnvironmentCosineAboutTheNormal) {
    Scene scene;
    scene.materials.push_back(Material{});
    Light env;
    env.type = LightType::Environment;
    env.intensity = vec3(0.25f, 0.5f, 1.0f);
    scene.lights.push_back(env);
    auto arrays = buildSceneArrays(scene);
    test::LightKernel kernel(arrays);
    uint32_t seed = 400;
    for (vec3 n : {vec3(0.36f, 0.48f, 0.8f), vec3(0.0f, 0.0f, -1.0f)}) {
        const std::string name = "environment_n" + std::to_string(seed - 400);
        SCOPED_TRACE(name);
        const vec3 x(1.0f, 2.0f, 3.0f);
        const auto samples = kernel.sample(0, x, n, gpu::SPHERE_SOLID_ANGLE, seed++, kSamples);
        checkConsistency(name, samples, [](const LightTestRecord&) { return Allowance{}; }, 0.0);
        size_t bad = 0;
        for (const auto& r : samples)
            if (accepted(r) && (r.radiance != env.intensity || r.dist != std::numeric_limits<float>::max())) ++bad;
        EXPECT_EQ(bad, 0u) << name << ": radiance must be L and the distance FLOAT_MAX";
        // Cosine about n on the direction sphere in the frame of n; the hemisphere's rim is a
        // row edge (cap 1).
        const test::Frame frame{dvec3(n)};
        std::vector<vec3> local(samples.size());
        for (size_t i = 0; i < samples.size(); ++i)
            local[i] = accepted(samples[i]) ? vec3(frame.toLocal(dvec3(samples[i].wi))) : vec3(0.0f);
        test::SphereChi2Options options;
        options.capOneMinusCos = 1.0;
        options.significance = kAlpha;
        options.numTests = kChi2Tests;
        options.dumpName = "chi2_light_" + name;
        const auto r = test::chi2TestSphere(
            local,
            [&](const std::vector<vec3>& dirs) {
                std::vector<vec3> world(dirs.size());
                for (size_t i = 0; i < dirs.size(); ++i) world[i] = vec3(frame.toWorld(dvec3(dirs[i])));
                return kernel.pdf(0, x, n, gpu::SPHERE_SOLID_ANGLE, world);
            },
            options);
        EXPECT_TRUE(r.passed) << name << ": " << r.message;
        EXPECT_NEAR(r.pdfIntegral, 1.0, r.integralTolerance) << name << ": " << r.message;
        std::printf("[ %s ] declined %zu; %s\n", name.c_str(), countDeclined(samples), r.message.c_str());
    }
}

// ---- Delta lights ------------------------------------------------------------------------------------

TEST(LightSampling, PointAndDirectionalAreExact) {
    // Point light at x + (1, 2, 2): d = 3 exactly, wi = (1, 2, 2) / 3, radiance I / 9 with
    // I = (9, 18, 4.5): (1, 2, 0.5). Directional light travelling along (0, -3, 4): wi is
    // minus the normalized direction, the radiance the irradiance E, the distance FLOAT_MAX.
    // GLSL's division may be off by 2.5 ULP, its sqrt by as much: 3 ULP (4e-7) relative.
    Scene scene;
    scene.materials.push_back(Material{});
    Light point;
    point.type = LightType::Point;
    const vec3 x(0.5f, -1.0f, 0.25f);
    point.position = x + vec3(1.0f, 2.0f, 2.0f);
    point.intensity = vec3(9.0f, 18.0f, 4.5f);
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = vec3(0.0f, -3.0f, 4.0f);
    sun.intensity = vec3(2.0f, 3.0f, 5.0f);
    scene.lights = {point, sun};
    auto arrays = buildSceneArrays(scene);
    test::LightKernel kernel(arrays);
    auto near = [](double a, double b) { return std::abs(a - b) <= 3.0 * std::ldexp(1.0, -23) * std::abs(b); };
    for (uint32_t light : {0u, 1u}) {
        SCOPED_TRACE(light == 0 ? "point" : "directional");
        const auto samples = kernel.sample(light, x, vec3(0, 0, 1), gpu::SPHERE_SOLID_ANGLE, 500 + light, 4096);
        const dvec3 wi = light == 0 ? dvec3(1.0, 2.0, 2.0) / 3.0 : dvec3(0.0, 0.6, -0.8);
        const dvec3 radiance = light == 0 ? dvec3(1.0, 2.0, 0.5) : dvec3(2.0, 3.0, 5.0);
        size_t bad = 0;
        for (const auto& r : samples) {
            const bool ok = accepted(r) && (r.flags & gpu::LIGHT_TEST_DELTA) && r.pdf == 1.0f &&
                            r.tracedPdf == 0.0f &&  // lightPdf of a delta light: no density
                            near(r.wi.x, wi.x) && near(r.wi.y, wi.y) && near(r.wi.z, wi.z) &&
                            near(r.radiance.x, radiance.x) && near(r.radiance.y, radiance.y) &&
                            near(r.radiance.z, radiance.z) &&
                            (light == 0 ? near(r.dist, 3.0) : r.dist == std::numeric_limits<float>::max());
            if (!ok && bad++ < 3)
                ADD_FAILURE() << "wi (" << r.wi.x << ", " << r.wi.y << ", " << r.wi.z << ") radiance (" << r.radiance.x
                              << ", " << r.radiance.y << ", " << r.radiance.z << ") dist " << r.dist << " pdf " << r.pdf
                              << " flags " << r.flags << " lightPdf " << r.tracedPdf;
        }
        EXPECT_EQ(bad, 0u);
    }
}

// ---- The harness rejects wrong pdfs (test of the test) ------------------------------------------------

TEST(LightSamplingChi2, RejectsCapPdfForSolidAngleSamples) {
    // Both densities integrate to 1 over the visible cap: only the histogram can tell.
    const SphereSetup s = sphereSetups()[1];
    auto arrays = buildSceneArrays(sceneWithShape(sphereShape(s.center, s.radius)));
    test::LightKernel kernel(arrays);
    const SphereCapChart chart(s.center, s.radius, s.x);
    LightCase lc{"expected_failure_sphere_cap_pdf_vs_solid_angle", 0, s.x, vec3(0, 0, 1), gpu::SPHERE_SOLID_ANGLE};
    const auto samples = kernel.sample(0, s.x, lc.n, gpu::SPHERE_SOLID_ANGLE, 600, kSamples);
    const auto r = chartChi2(kernel, lc, chart, samples, gpu::SPHERE_CAP, lc.name);
    EXPECT_FALSE(r.passed) << r.message;
    EXPECT_LT(r.pValue, r.threshold) << r.message;
    std::printf("[ expected failure ] %s\n", r.message.c_str());
}

TEST(LightSamplingChi2, RejectsMeshPdfWithoutAreaWeighting) {
    // The density if triangles were chosen uniformly, 1 / (K A_k) per unit area instead of
    // 1 / A: it integrates to 1 as well.
    const MeshSetup m = meshSetup(true, true);
    const MeshChart chart(m.triangles);
    auto arrays = buildSceneArrays(sceneWithShape(m.shape));
    test::LightKernel kernel(arrays);
    double total = 0.0;
    for (int k = 0; k < chart.parts(); ++k) total += chart.area(k);
    LightCase lc{"expected_failure_mesh_uniform_triangles", 0, vec3(0.0f)};
    const auto samples = kernel.sample(0, lc.x, lc.n, gpu::SPHERE_SOLID_ANGLE, 601, kSamples);
    const auto r = chartChi2(kernel, lc, chart, samples, gpu::SPHERE_SOLID_ANGLE, lc.name, 0.0,
                             [&](const Located& at) { return total / (chart.parts() * chart.area(at.part)); });
    EXPECT_FALSE(r.passed) << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, r.integralTolerance) << r.message;
    std::printf("[ expected failure ] %s\n", r.message.c_str());
}
