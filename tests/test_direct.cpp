// The direct-illumination integrator against closed forms, under every strategy. The scenes
// put one light above a diffuse plane y = 0 (albedo a) with nothing in between; the camera
// looks straight down on a 3 x 3 patch beside the light, so each pixel's expected value is
// a/pi * E(x) averaged over the pixel, with E the irradiance:
//   point        E = I cos(theta) / d^2                             (lecture, "Point Light")
//   spot         E = I s^2 cos(theta) / d^2, s the glTF falloff     (SCENE_FORMAT.md `spot`)
//   directional  E = E_perp cos(theta)
//   polygon      E = Le/2 |sum_i Theta_i (Gamma_i . n)|             (Lambert; Arvo 1995)
//   sphere       E = pi Le (r/d)^2 cos(theta), sphere above the horizon
// Delta lights give the same estimate for every sample of a pixel, so only the spread over
// the pixel varies and its variance is known exactly; for area lights the per-sample variance
// is unknown and a block t-test of the residuals checks unbiasedness instead.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
using test::polygonIrradiance;

namespace {

constexpr double kAlbedo = 0.6;
constexpr int kSize = 32;
constexpr double kAlpha = 1e-3;

json planeScene(int spp, json integrator) {
    return {
        {"camera", test::topDownCamera(3.0, 0.0, 1.5)},
        {"film", {{"width", kSize}, {"height", kSize}}},
        {"sampler", {{"spp", spp}, {"seed", 11}}},
        {"integrator", integrator},
        {"materials", {{"plane", {{"type", "diffuse"}, {"albedo", {kAlbedo, kAlbedo, kAlbedo}}}},
                       {"black", {{"type", "diffuse"}, {"albedo", {0, 0, 0}}}}}},
        {"shapes",
         json::array({{{"type", "quad"}, {"origin", {-50, 0, -50}}, {"edge_u", {0, 0, 100}}, {"edge_v", {100, 0, 0}},
                       {"material", "plane"}}})},
        {"lights", json::array()},
    };
}

json direct(const std::string& strategy, json extra = json::object()) {
    json j = {{"type", "direct"}, {"strategy", strategy}};
    j.update(extra);
    return j;
}

const std::vector<std::string> kStrategies = {"light", "bsdf", "mis", "mixture"};

// Delta lights: per-pixel check with the exact jitter variance, the pixel integral and that
// variance taken on a sub x sub grid. A spot's cone edge needs a finer grid than the default:
// a pixel lit only in a sliver between grid points would look unlit (expected 0, variance 0)
// to the reference.
void expectDeltaLightMatches(json doc, const std::function<double(glm::dvec3)>& radiance, const std::string& name,
                             int sub = 8) {
    const int spp = 64;
    for (const std::string& strategy : kStrategies) {
        doc["integrator"] = direct(strategy);
        doc["sampler"]["spp"] = spp;
        Scene scene = test::sceneFromJson(doc, name + "-" + strategy);
        Image image = test::renderScene(scene);
        std::vector<double> jitter;
        std::vector<double> expected = test::expectedTopDown(scene, radiance, sub, &jitter);
        double z = test::zScore(kAlpha, kSize * kSize * int(kStrategies.size()));
        int failures = 0;
        for (size_t p = 0; p < expected.size(); ++p) {
            double tol = z * std::sqrt(jitter[p] / spp) + 1e-5 * expected[p] + 1e-6;
            if (std::abs(image.rgb[3 * p] - expected[p]) > tol) ++failures;
        }
        EXPECT_EQ(failures, 0) << name << " under strategy " << strategy;
        if (failures) writeExr(test::outputPath(name + "-" + strategy + ".exr"), image);
    }
}

// An irregular hexagon at height h, counter-clockwise seen from below (its front faces
// the plane), for a fan of triangles of different areas.
std::vector<glm::dvec3> hexagonOutline(double h) {
    return {{0.9, h, 0.0}, {0.3, h, 0.7}, {-0.4, h, 0.5}, {-0.8, h, 0.0}, {-0.3, h, -0.9}, {0.5, h, -0.6}};
}

// An emitting mesh (radiance Le, black) of the triangles from the outline's centre
// (0, h, 0) to each of its edges, wound as the outline is.
json fanMesh(const std::vector<glm::dvec3>& outline, double Le) {
    const double h = outline[0].y;
    json positions = json::array({0.0, h, 0.0});
    for (auto& v : outline) positions.insert(positions.end(), {v.x, v.y, v.z});
    json indices = json::array();
    const int n = int(outline.size());
    for (int i = 0; i < n; ++i) indices.insert(indices.end(), {0, 1 + i, 1 + (i + 1) % n});
    return {{"type", "mesh"},
            {"positions", positions},
            {"indices", indices},
            {"emission", {Le, Le, Le}},
            {"material", "black"}};
}

std::vector<json> allStrategies(json extra = json::object()) {
    std::vector<json> out;
    for (const std::string& s : kStrategies) out.push_back(direct(s, extra));
    out.push_back(direct("mis", {{"heuristic", "balance"}}));
    out.push_back(direct("mis", {{"light_samples", 2}, {"bsdf_samples", 3}}));
    return out;
}

}  // namespace

TEST(DirectClosedForm, PointLight) {
    const double I = 20.0, h = 1.5;
    json doc = planeScene(64, direct("light"));
    doc["lights"].push_back({{"type", "point"}, {"position", {0, h, 0}}, {"intensity", {I, I, I}}});
    expectDeltaLightMatches(doc, [&](glm::dvec3 x) {
        double d2 = x.x * x.x + x.z * x.z + h * h;
        return kAlbedo / M_PI * I * (h / std::sqrt(d2)) / d2;
    }, "point");
}

TEST(DirectClosedForm, PointLightGivenByPower) {
    // power P = 4 pi I: the same image as intensity I.
    const double I = 5.0, h = 1.0;
    json doc = planeScene(64, direct("light"));
    doc["lights"].push_back({{"type", "point"}, {"position", {0.5, h, 0.5}}, {"power", {4 * M_PI * I, 4 * M_PI * I, 4 * M_PI * I}}});
    expectDeltaLightMatches(doc, [&](glm::dvec3 x) {
        glm::dvec3 to = glm::dvec3(0.5, h, 0.5) - x;
        double d2 = glm::dot(to, to);
        return kAlbedo / M_PI * I * (h / std::sqrt(d2)) / d2;
    }, "point-power");
}

// Spot lights over the plane, with their axes tilted so that the 3 x 3 patch holds points
// inside the inner cone, in the falloff band and outside the outer cone (counted, so the
// test cannot pass on one region alone); one axis has z < 0, the other z > 0 (both halves of
// the octahedral axis encoding).
TEST(DirectClosedForm, SpotLightInsideOnAndOutsideTheCone) {
    const double I = 12.0;
    const glm::dvec3 pos(3.2, 1.0, -0.1);
    const double inner = 20.0, outer = 40.0;
    const double cosInner = std::cos(inner * M_PI / 180.0), cosOuter = std::cos(outer * M_PI / 180.0);
    for (glm::dvec3 axisIn : {glm::dvec3(-0.3, -1.0, -0.25), glm::dvec3(0.2, -1.0, 0.3)}) {
        glm::dvec3 axis = glm::normalize(axisIn);
        auto falloff = [&](glm::dvec3 x) {
            double cosT = glm::dot(glm::normalize(x - pos), axis);
            double s = std::clamp((cosT - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
            return s * s;
        };
        int inside = 0, band = 0, outside = 0;
        for (int i = 0; i < kSize; ++i)
            for (int j = 0; j < kSize; ++j) {
                glm::dvec3 x(1.5 + 3.0 * (i + 0.5) / kSize, 0.0, -1.5 + 3.0 * (j + 0.5) / kSize);
                double f = falloff(x);
                (f >= 1.0 ? inside : f > 0.0 ? band : outside) += 1;
            }
        EXPECT_GT(inside, 50);
        EXPECT_GT(band, 50);
        EXPECT_GT(outside, 50);
        json doc = planeScene(64, direct("light"));
        doc["lights"].push_back({{"type", "spot"},
                                 {"position", {pos.x, pos.y, pos.z}},
                                 {"direction", {axisIn.x, axisIn.y, axisIn.z}},
                                 {"inner_angle", inner},
                                 {"outer_angle", outer},
                                 {"intensity", {I, I, I}}});
        expectDeltaLightMatches(
            doc,
            [&](glm::dvec3 x) {
                glm::dvec3 to = pos - x;
                double d2 = glm::dot(to, to);
                return kAlbedo / M_PI * I * falloff(x) * (to.y / std::sqrt(d2)) / d2;
            },
            "spot", 64);
    }
}

TEST(DirectClosedForm, SpotLightGivenByPowerWithTheDefaultInnerAngle) {
    // inner_angle 0: s falls linearly in cos t from the axis to the 60 degree edge; power
    // P = 2 pi I ((1 - 1) + (1 - cos 60) / 3) = pi I / 3.
    const double I = 9.0, h = 1.2;
    const double cosOuter = 0.5;
    const double P = 2.0 * M_PI * I * (1.0 - cosOuter) / 3.0;
    json doc = planeScene(64, direct("light"));
    doc["lights"].push_back({{"type", "spot"},
                             {"position", {3.0, h, 0.0}},
                             {"direction", {0, -1, 0}},
                             {"outer_angle", 60},
                             {"power", {P, P, P}}});
    expectDeltaLightMatches(
        doc,
        [&](glm::dvec3 x) {
            glm::dvec3 to = glm::dvec3(3.0, h, 0.0) - x;
            double d2 = glm::dot(to, to);
            double cosT = to.y / std::sqrt(d2);
            double s = std::clamp((cosT - cosOuter) / (1.0 - cosOuter), 0.0, 1.0);
            return kAlbedo / M_PI * I * s * s * cosT / d2;
        },
        "spot-power", 64);
}

TEST(DirectClosedForm, DirectionalLight) {
    const double E = 3.0;
    glm::dvec3 travel = glm::normalize(glm::dvec3(-1, -2, -0.5));
    json doc = planeScene(64, direct("light"));
    doc["lights"].push_back({{"type", "directional"}, {"direction", {-1, -2, -0.5}}, {"irradiance", {E, E, E}}});
    expectDeltaLightMatches(doc, [&](glm::dvec3) { return kAlbedo / M_PI * E * -travel.y; }, "directional");
}

// Vertex normals shade: the plane as a mesh whose vertex normals all lean the same way, so
// the shading normal is that direction everywhere and a directional light's reflected
// radiance is albedo / pi * E * cos(angle to the shading normal) exactly, not the geometric
// normal's cosine.
TEST(DirectClosedForm, DirectionalLightOnMeshWithVertexNormals) {
    const double E = 3.0;
    glm::dvec3 travel = glm::normalize(glm::dvec3(-1, -2, -0.5));
    glm::dvec3 shading = glm::normalize(glm::dvec3(0.3, 1.0, 0.2));
    json doc = planeScene(64, direct("light"));
    json normals = json::array();
    for (int i = 0; i < 4; ++i) normals.insert(normals.end(), {shading.x, shading.y, shading.z});
    doc["shapes"][0] = {{"type", "mesh"},
                        {"positions", {-50, 0, -50, -50, 0, 50, 50, 0, 50, 50, 0, -50}},
                        {"indices", {0, 1, 2, 0, 2, 3}},
                        {"normals", normals},
                        {"material", "plane"}};
    doc["lights"].push_back({{"type", "directional"}, {"direction", {-1, -2, -0.5}}, {"irradiance", {E, E, E}}});
    expectDeltaLightMatches(
        doc, [&](glm::dvec3) { return kAlbedo / M_PI * E * glm::dot(-travel, shading); }, "vertex-normals");
}

TEST(DirectClosedForm, QuadLightEveryStrategy) {
    const double Le = 5.0, h = 1.5;
    json doc = planeScene(256, direct("light"));
    doc["shapes"].push_back({{"type", "quad"}, {"origin", {-0.5, h, -0.5}}, {"edge_u", {1, 0, 0}}, {"edge_v", {0, 0, 1}},
                             {"emission", {Le, Le, Le}}, {"material", "black"}});
    std::vector<glm::dvec3> quad = {{-0.5, h, -0.5}, {0.5, h, -0.5}, {0.5, h, 0.5}, {-0.5, h, 0.5}};
    test::expectTopDownMatches(
        doc, allStrategies({{"quad_sampling", "area"}}),
        [&](glm::dvec3 x) { return kAlbedo / M_PI * polygonIrradiance(quad, x, Le); }, "quad", kAlpha);
}

TEST(DirectClosedForm, QuadLightsInSolidAngleEveryStrategy) {
    // A rectangle (spherical rectangle) and a skewed parallelogram (two spherical triangles,
    // and under both sampling modes), close enough that the solid angle is large.
    const double Le = 5.0, h = 0.8;
    struct Quad {
        std::string name;
        glm::dvec3 origin, u, v;
    };
    const Quad quads[] = {{"rectangle", {-0.5, h, -0.5}, {1, 0, 0}, {0, 0, 1}},
                          {"parallelogram", {-0.6, h, -0.4}, {1, 0, 0}, {0.7, 0, 0.8}}};
    for (const Quad& q : quads) {
        json doc = planeScene(256, direct("light"));
        // edge_u x edge_v must face down (-y) toward the plane: u = x, v = z gives -y.
        doc["shapes"].push_back({{"type", "quad"},
                                 {"origin", {q.origin.x, q.origin.y, q.origin.z}},
                                 {"edge_u", {q.u.x, q.u.y, q.u.z}},
                                 {"edge_v", {q.v.x, q.v.y, q.v.z}},
                                 {"emission", {Le, Le, Le}},
                                 {"material", "black"}});
        std::vector<glm::dvec3> outline = {q.origin, q.origin + q.u, q.origin + q.u + q.v, q.origin + q.v};
        std::vector<json> integrators = allStrategies({{"quad_sampling", "solid_angle"}});
        if (q.name == "parallelogram")
            for (json& j : allStrategies({{"quad_sampling", "area"}})) integrators.push_back(j);
        test::expectTopDownMatches(
            doc, integrators, [&](glm::dvec3 x) { return kAlbedo / M_PI * polygonIrradiance(outline, x, Le); },
            "quad-solid-angle-" + q.name, kAlpha);
    }
}

TEST(DirectClosedForm, OneSidedQuadLightFacingAwayGivesNothing) {
    json doc = planeScene(16, direct("mis"));
    doc["shapes"].push_back({{"type", "quad"}, {"origin", {-0.5, 1.5, -0.5}}, {"edge_u", {0, 0, 1}}, {"edge_v", {1, 0, 0}},
                             {"emission", {5, 5, 5}}});  // front normal +y: emits upwards
    for (const std::string& s : kStrategies) {
        doc["integrator"] = direct(s);
        Image image = test::renderJson(doc, "quad-away-" + s);
        for (float v : image.rgb) ASSERT_EQ(v, 0.0f) << s;
    }
}

TEST(DirectClosedForm, SphereLightEverySamplingAndStrategy) {
    const double Le = 4.0, r = 0.4, h = 1.5;
    json doc = planeScene(256, direct("light"));
    doc["shapes"].push_back({{"type", "sphere"}, {"center", {0, h, 0}}, {"radius", r}, {"emission", {Le, Le, Le}},
                             {"material", "black"}});
    std::vector<json> integrators = allStrategies();
    for (const char* sampling : {"area", "cap"}) {
        integrators.push_back(direct("light", {{"sphere_sampling", sampling}}));
        integrators.push_back(direct("mis", {{"sphere_sampling", sampling}}));
    }
    test::expectTopDownMatches(
        doc, integrators,
        [&](glm::dvec3 x) {
            double d2 = x.x * x.x + x.z * x.z + h * h;
            return kAlbedo / M_PI * M_PI * Le * r * r / d2 * (h / std::sqrt(d2));
        },
        "sphere", kAlpha);
}

TEST(DirectClosedForm, MeshLightIsSumOfItsTriangles) {
    // The polygon formula over the fan's outline equals the sum over its triangles.
    const double Le = 5.0, h = 1.2;
    const std::vector<glm::dvec3> outline = hexagonOutline(h);
    json doc = planeScene(256, direct("light"));
    doc["shapes"].push_back(fanMesh(outline, Le));
    test::expectTopDownMatches(
        doc, allStrategies(), [&](glm::dvec3 x) { return kAlbedo / M_PI * polygonIrradiance(outline, x, Le); }, "mesh",
        kAlpha);
}

TEST(DirectClosedForm, MeshLightTrianglesInSolidAngleEveryStrategy) {
    // The fan of MeshLightIsSumOfItsTriangles, lower (large solid angles), each triangle
    // sampled in its spherical triangle.
    const double Le = 5.0, h = 0.6;
    const std::vector<glm::dvec3> outline = hexagonOutline(h);
    json doc = planeScene(256, direct("light"));
    doc["shapes"].push_back(fanMesh(outline, Le));
    test::expectTopDownMatches(
        doc, allStrategies({{"triangle_sampling", "solid_angle"}}),
        [&](glm::dvec3 x) { return kAlbedo / M_PI * polygonIrradiance(outline, x, Le); }, "mesh-solid-angle", kAlpha);
}

TEST(DirectClosedForm, IrradianceIsIndependentOfSphereRadius) {
    // Lecture, "Sphere Light - Validation": spheres of equal power P and any radius light the
    // plane exactly like a point light of intensity P / (4 pi).
    const double P = 40.0, h = 1.5;
    auto expected = [&](glm::dvec3 x) {
        double d2 = x.x * x.x + x.z * x.z + h * h;
        return kAlbedo / M_PI * P / (4 * M_PI) * (h / std::sqrt(d2)) / d2;
    };
    for (double r : {0.6, 0.05}) {
        json doc = planeScene(256, direct("light"));
        doc["shapes"].push_back({{"type", "sphere"}, {"center", {0, h, 0}}, {"radius", r}, {"power", {P, P, P}},
                                 {"material", "black"}});
        test::expectTopDownMatches(doc, {direct("light"), direct("mis")}, expected, "radius-" + std::to_string(r),
                                   kAlpha);
    }
    json doc = planeScene(16, direct("light"));
    doc["lights"].push_back({{"type", "point"}, {"position", {0, h, 0}}, {"power", {P, P, P}}});
    expectDeltaLightMatches(doc, expected, "radius-point");
}

TEST(DirectVariance, SphereSamplingOrderSolidAngleCapArea) {
    const double Le = 2.0, r = 0.9, h = 1.2;
    auto expectedL = [&](glm::dvec3 x) {
        double d2 = x.x * x.x + x.z * x.z + h * h;
        return kAlbedo * Le * r * r / d2 * (h / std::sqrt(d2));
    };
    double mse[3];
    const char* samplings[3] = {"solid_angle", "cap", "area"};
    for (int i = 0; i < 3; ++i) {
        json doc = planeScene(16, direct("light", {{"sphere_sampling", samplings[i]}}));
        doc["camera"] = test::topDownCamera(2.0, 0.0, 1.0);  // close to the light: shapes matter
        doc["shapes"].push_back({{"type", "sphere"}, {"center", {0, h, 0}}, {"radius", r}, {"emission", {Le, Le, Le}},
                                 {"material", "black"}});
        Scene scene = test::sceneFromJson(doc, std::string("order-") + samplings[i]);
        mse[i] = test::meanSquaredError(test::renderScene(scene), test::expectedTopDown(scene, expectedL));
    }
    // Each MSE averages 1024 independent squared errors (relative spread about 5%).
    EXPECT_LT(mse[0], mse[1]) << "solid_angle " << mse[0] << " cap " << mse[1];
    EXPECT_LT(mse[1], mse[2]) << "cap " << mse[1] << " area " << mse[2];
}

TEST(DirectVariance, QuadSolidAngleBelowAreaCloseUp) {
    // A 2 x 2 quad light 0.3 above the floor and the 2 x 2 patch of floor beside it (the camera
    // looks down past the light's edge): area sampling wastes samples on the far part of the
    // light and its 1/pdf blows up at grazing angles. Independent samples, so that the MSE is
    // the per-sample variance / spp.
    const double Le = 2.0, h = 0.3;
    std::vector<glm::dvec3> quad = {{-2, h, -1}, {0, h, -1}, {0, h, 1}, {-2, h, 1}};
    double mse[2];
    const char* samplings[2] = {"solid_angle", "area"};
    for (int i = 0; i < 2; ++i) {
        json doc = planeScene(16, direct("light", {{"quad_sampling", samplings[i]}}));
        doc["sampler"]["type"] = "independent";
        doc["camera"] = test::topDownCamera(1.0, 0.0, 1.0);
        doc["shapes"].push_back({{"type", "quad"},
                                 {"origin", {-2, h, -1}},
                                 {"edge_u", {2, 0, 0}},
                                 {"edge_v", {0, 0, 2}},
                                 {"emission", {Le, Le, Le}},
                                 {"material", "black"}});
        Scene scene = test::sceneFromJson(doc, std::string("quad-order-") + samplings[i]);
        mse[i] = test::meanSquaredError(test::renderScene(scene), test::expectedTopDown(scene, [&](glm::dvec3 x) {
                                            return kAlbedo / M_PI * polygonIrradiance(quad, x, Le);
                                        }));
    }
    // Each MSE averages 1024 pixels' squared errors of 16 independent samples.
    std::printf("[ quad sampling ] MSE solid_angle %.4g area %.4g: ratio area / solid_angle %.3g\n", mse[0], mse[1],
                mse[1] / mse[0]);
    EXPECT_LT(mse[0], mse[1]) << "solid_angle " << mse[0] << " area " << mse[1];
}

TEST(DirectVariance, MseFallsAsOneOverN) {
    const double Le = 5.0, h = 1.5;
    std::vector<glm::dvec3> quad = {{-0.5, h, -0.5}, {0.5, h, -0.5}, {0.5, h, 0.5}, {-0.5, h, 0.5}};
    std::vector<double> logN, logMse;
    for (int spp : {4, 16, 64, 256}) {
        json doc = planeScene(spp, direct("light"));
        // MSE ~ 1/N is the rate of independent samples; Sobol' samples (the default) converge
        // faster on this smooth integrand (test_sampler_estimates.cpp), so that is not tested here.
        doc["sampler"]["type"] = "independent";
        doc["integrator"]["quad_sampling"] = "area";
        doc["shapes"].push_back({{"type", "quad"}, {"origin", {-0.5, h, -0.5}}, {"edge_u", {1, 0, 0}},
                                 {"edge_v", {0, 0, 1}}, {"emission", {Le, Le, Le}}});
        Scene scene = test::sceneFromJson(doc, "slope-" + std::to_string(spp));
        double mse = test::meanSquaredError(test::renderScene(scene), test::expectedTopDown(scene, [&](glm::dvec3 x) {
            return kAlbedo / M_PI * polygonIrradiance(quad, x, Le);
        }));
        logN.push_back(std::log(double(spp)));
        logMse.push_back(std::log(mse));
    }
    // Least-squares slope of log MSE against log N. Each log MSE is within about 0.05 of its
    // mean (1024 pixels), so the slope over a factor 64 in N is within about 0.02 of -1.
    double mx = 0, my = 0;
    for (size_t i = 0; i < logN.size(); ++i) mx += logN[i] / logN.size(), my += logMse[i] / logN.size();
    double sxy = 0, sxx = 0;
    for (size_t i = 0; i < logN.size(); ++i) sxy += (logN[i] - mx) * (logMse[i] - my), sxx += std::pow(logN[i] - mx, 2);
    double slope = sxy / sxx;
    EXPECT_NEAR(slope, -1.0, 0.1);
}

namespace {

// The Veach & Guibas scene of scenes/veach_mis.json, smaller, with the given integrator.
json veachScene(int width, int height, int spp, uint32_t seed, json integrator) {
    std::ifstream in(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/veach_mis.json");
    json doc = json::parse(in);
    doc["film"] = {{"width", width}, {"height", height}};
    doc["sampler"] = {{"spp", spp}, {"seed", seed}};
    doc["integrator"] = integrator;
    return doc;
}

std::vector<double> channel0(const Image& image) {
    std::vector<double> out(size_t(image.width) * image.height);
    for (size_t p = 0; p < out.size(); ++p) out[p] = image.rgb[3 * p];
    return out;
}

double relMse(const Image& image, const Image& reference) {
    double sum = 0;
    for (size_t i = 0; i < image.rgb.size(); ++i)
        sum += std::pow(image.rgb[i] - reference.rgb[i], 2) / (std::pow(reference.rgb[i], 2) + 1e-2);
    return sum / double(image.rgb.size());
}

}  // namespace

TEST(DirectConsistency, EveryStrategyConvergesToTheSameImageOnGlossySurfaces) {
    // Independent renders (different seeds) of each strategy must agree with MIS: the
    // difference image has mean zero (block t-test on the difference).
    const int spp = 512;
    for (bool closeUp : {false, true}) {
        Image mis = test::renderJson(test::glossyPlatesScene(spp, 1, direct("mis"), closeUp), "glossy-agree-mis");
        std::vector<json> others = {direct("light"),
                                    direct("bsdf"),
                                    direct("mixture"),
                                    direct("mis", {{"heuristic", "balance"}}),
                                    direct("mis", {{"light_samples", 3}, {"bsdf_samples", 1}}),
                                    direct("light", {{"sphere_sampling", "cap"}}),
                                    direct("light", {{"light_selection", "uniform"}})};
        for (size_t i = 0; i < others.size(); ++i) {
            Image image = test::renderJson(test::glossyPlatesScene(spp, 2 + uint32_t(i), others[i], closeUp),
                                           "glossy-agree-" + std::to_string(i));
            std::string report;
            EXPECT_EQ(test::blockTTest(image, channel0(mis), 8, kAlpha, 2 * int(others.size()), &report), 0)
                << (closeUp ? "close-up " : "wide ") << others[i].dump() << ": " << report;
            if (::testing::Test::HasFailure())
                writeExr(test::outputPath("glossy-agree-" + std::to_string(i) + ".exr"), image);
        }
    }
}

TEST(DirectVariance, MisBeatsLightAndBsdfSamplingOnTheVeachScene) {
    Image reference = test::renderJson(veachScene(128, 80, 512, 100, direct("mis")), "veach-reference");
    double light = relMse(test::renderJson(veachScene(128, 80, 8, 1, direct("light")), "veach-light"), reference);
    double bsdf = relMse(test::renderJson(veachScene(128, 80, 8, 1, direct("bsdf")), "veach-bsdf"), reference);
    double mis = relMse(test::renderJson(veachScene(128, 80, 8, 1, direct("mis")), "veach-mis"), reference);
    EXPECT_LT(mis, light) << "mis " << mis << " light " << light;
    EXPECT_LT(mis, bsdf) << "mis " << mis << " bsdf " << bsdf;
}
