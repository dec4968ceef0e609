// Light selection without rendering: selectLight (shaders/lights/lights.glsl) draws
// each light of the full table, the delta-only and the continuous-only sub-tables with the
// probability SCENE_FORMAT.md defines (uniform, or proportional to power), and leaves a number
// uniform on [0,1) whatever the light (which the light's sample uses), chi-square tested
// jointly over 2^20 GPU draws each; Light::selectionProb and RenderParams' deltaScale / continuousScale agree
// with the sub-tables; the mesh-light triangle table draws by area. On the CPU, the alias
// tables of host/render/alias_table.cpp reproduce their weights exactly when enumerated.
//
// Significance: alpha = 0.01 for the file, Sidak-corrected over kChi2Tests tests; fixed seeds.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "chi2.h"
#include "light_kernel.h"
#include "render/alias_table.h"
#include "render/scene_arrays.h"

using namespace penumbra;
using glm::vec3;

namespace {

constexpr double kAlpha = 0.01;
// Chi-square tests in this file that must pass: 2 selections x 3 tables + 1 mesh table.
constexpr int kChi2Tests = 7;
constexpr uint32_t kDraws = 1u << 20;
constexpr double kPi = std::numbers::pi;

// Two point lights (one of intensity 0: it carries no power), a directional light, an
// environment, and a quad, a sphere and a two-sided mesh light of three triangles.
Scene selectionScene(LightSelection selection) {
    Scene scene;
    scene.materials.push_back(Material{});
    scene.integrator.lightSelection = selection;
    auto light = [](LightType type, vec3 intensity) {
        Light l;
        l.type = type;
        l.intensity = intensity;
        l.position = vec3(0.0f, 3.0f, 0.0f);
        l.direction = vec3(0.0f, -1.0f, 0.2f);
        return l;
    };
    scene.lights = {light(LightType::Point, vec3(1.0f, 2.0f, 3.0f)), light(LightType::Point, vec3(0.0f)),
                    light(LightType::Directional, vec3(0.5f)), light(LightType::Environment, vec3(0.02f, 0.03f, 0.04f))};
    Shape quad;
    quad.type = ShapeType::Quad;
    quad.origin = vec3(-1.0f, 2.0f, -1.0f);
    quad.edgeU = vec3(2.0f, 0.0f, 0.0f);
    quad.edgeV = vec3(0.0f, 0.0f, 1.5f);
    quad.emission = vec3(3.0f);
    Shape sphere;
    sphere.type = ShapeType::Sphere;
    sphere.center = vec3(2.0f, 1.0f, 0.0f);
    sphere.radius = 0.25f;
    sphere.emission = vec3(10.0f, 20.0f, 30.0f);
    Shape mesh;
    mesh.type = ShapeType::Mesh;
    mesh.positions = {vec3(-3, 0, 0), vec3(-2, 0, 0), vec3(-3, 1, 0), vec3(-3, 0, 1), vec3(-2.9f, 0, 1), vec3(-3, 0.1f, 1)};
    mesh.indices = {0, 1, 2, 3, 4, 5, 0, 2, 3};
    mesh.emission = vec3(1.0f);
    mesh.twoSided = true;
    scene.shapes = {quad, sphere, mesh};
    return scene;
}

// Power of each light per SCENE_FORMAT.md, computed here from the scene and the arrays'
// areas (mean of RGB): area lights pi Le A (twice when two-sided), points 4 pi I,
// directional pi R^2 E, environment 4 pi^2 R^2 L, R = half the diagonal of the bounds.
std::vector<double> expectedWeights(const SceneArrays& a, LightSelection selection) {
    glm::dvec3 lo(1e30), hi(-1e30);
    for (const auto& p : a.bvh.primitives) {
        const uint32_t type = p.typeAndNormals & gpu::PRIM_TYPE_MASK;
        std::vector<glm::dvec3> pts;
        if (type == gpu::PRIM_SPHERE) {
            pts = {glm::dvec3(p.p0) - double(p.p1.x), glm::dvec3(p.p0) + double(p.p1.x)};
        } else if (type == gpu::PRIM_QUAD) {
            pts = {p.p0, p.p0 + p.p1, p.p0 + p.p2, p.p0 + p.p1 + p.p2};
        } else {
            pts = {p.p0, p.p1, p.p2};
        }
        for (auto q : pts) lo = glm::min(lo, q), hi = glm::max(hi, q);
    }
    const double R = 0.5 * glm::length(hi - lo);
    std::vector<double> w;
    for (const gpu::Light& l : a.lights) {
        if (selection == LightSelection::Uniform) {
            w.push_back(1.0);
            continue;
        }
        const double mean = (double(l.emission.x) + l.emission.y + l.emission.z) / 3.0;
        switch (l.type) {
            case gpu::LIGHT_POINT: w.push_back(4.0 * kPi * mean); break;
            case gpu::LIGHT_DIRECTIONAL: w.push_back(kPi * R * R * mean); break;
            case gpu::LIGHT_ENVIRONMENT: w.push_back(4.0 * kPi * kPi * R * R * mean); break;
            default: w.push_back(kPi * mean * l.area * ((l.flags & gpu::LIGHT_TWO_SIDED) ? 2.0 : 1.0));
        }
    }
    return w;
}

bool isDelta(const gpu::Light& l) { return l.type == gpu::LIGHT_POINT || l.type == gpu::LIGHT_DIRECTIONAL; }

// Draws from one table on the GPU (`table`: LIGHT_TEST_TABLE_LIGHTS or _MESH) and tests them
// against `pmf` (per item: light or primitive index; items not in the table have 0):
// counts, and the pmf the sampler returns with each draw. For the lights, the cells are
// (light, which of kRestBins equal parts of [0,1) the number left of the draw falls in),
// each of probability pmf / kRestBins: the light drawn and that number are independent, and
// the number uniform.
void checkTable(test::LightKernel& kernel, const std::string& name, uint32_t offset, uint32_t count,
                const std::vector<double>& pmf, uint32_t seed, uint32_t table = gpu::LIGHT_TEST_TABLE_LIGHTS) {
    constexpr size_t kRestBins = 8;
    const size_t bins = table == gpu::LIGHT_TEST_TABLE_LIGHTS ? kRestBins : 1;
    const auto draws = kernel.select(table, offset, count, seed, kDraws);
    std::vector<double> counts(pmf.size() * bins, 0.0);
    size_t badPmf = 0, outside = 0, badRest = 0;
    for (const auto& d : draws) {
        if (d.hitPrimitive >= pmf.size() || pmf[d.hitPrimitive] == 0.0) {
            ++outside;
            continue;
        }
        size_t bin = 0;
        if (bins > 1) {
            if (!(d.tracedT >= 0.0f && d.tracedT < 1.0f)) {
                ++badRest;
                continue;
            }
            bin = size_t(double(d.tracedT) * double(bins));
        }
        counts[d.hitPrimitive * bins + bin] += 1.0;
        // The float pmf of the table: the exact value to float rounding (a few 1e-8).
        if (std::abs(d.tracedPdf - pmf[d.hitPrimitive]) > 1e-6 * pmf[d.hitPrimitive]) ++badPmf;
    }
    EXPECT_EQ(outside, 0u) << name << ": drew lights that are not in the table or have probability 0";
    EXPECT_EQ(badPmf, 0u) << name << ": the draw returned a pmf that is not the light's";
    EXPECT_EQ(badRest, 0u) << name << ": the number left of a draw is outside [0,1)";
    // Only the lights in the table are outcomes (zero-probability cells hold nothing anyway).
    std::vector<double> c, p;
    for (size_t i = 0; i < pmf.size(); ++i)
        if (pmf[i] > 0.0)
            for (size_t b = 0; b < bins; ++b) c.push_back(counts[i * bins + b]), p.push_back(pmf[i] / double(bins));
    const auto r = test::chi2TestDiscrete(c, p, 0, {kAlpha, kChi2Tests, "chi2_selection_" + name});
    EXPECT_TRUE(r.passed) << name << ": " << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-12) << name;
    std::printf("[ %s ] %s\n", name.c_str(), r.message.c_str());
}

}  // namespace

TEST(LightSelection, FullDeltaAndContinuousTables) {
    uint32_t seed = 700;
    for (LightSelection selection : {LightSelection::Uniform, LightSelection::Power}) {
        const std::string mode = selection == LightSelection::Uniform ? "uniform" : "power";
        SCOPED_TRACE(mode);
        const Scene scene = selectionScene(selection);
        const SceneArrays a = buildSceneArrays(scene);
        const gpu::RenderParams params = makeRenderParams(scene, a);
        const std::vector<double> w = expectedWeights(a, selection);
        ASSERT_EQ(a.lights.size(), 7u);
        double all = 0.0, delta = 0.0, continuous = 0.0;
        for (size_t i = 0; i < w.size(); ++i) {
            all += w[i];
            (isDelta(a.lights[i]) ? delta : continuous) += w[i];
        }
        std::vector<double> pAll(w.size()), pDelta(w.size(), 0.0), pContinuous(w.size(), 0.0);
        for (size_t i = 0; i < w.size(); ++i) {
            pAll[i] = w[i] / all;
            (isDelta(a.lights[i]) ? pDelta[i] : pContinuous[i]) = w[i] / (isDelta(a.lights[i]) ? delta : continuous);
        }
        // selectionProb is the full table's pmf; the scales turn it into the sub-tables'.
        for (size_t i = 0; i < w.size(); ++i) {
            SCOPED_TRACE("light " + std::to_string(i));
            EXPECT_NEAR(a.lights[i].selectionProb, pAll[i], 1e-6 * pAll[i]);
            const double scale = isDelta(a.lights[i]) ? params.deltaScale : params.continuousScale;
            EXPECT_NEAR(a.lights[i].selectionProb * scale, isDelta(a.lights[i]) ? pDelta[i] : pContinuous[i],
                        1e-6 * pAll[i] * scale);
        }
        EXPECT_EQ(params.lightCount, 7u);
        EXPECT_EQ(params.deltaCount, 3u);  // both points (one of power 0) and the directional
        EXPECT_EQ(params.continuousCount, 4u);
        if (selection == LightSelection::Power) {
            EXPECT_EQ(pAll[1], 0.0);  // the dark point light
        }

        test::LightKernel kernel(a);
        checkTable(kernel, mode + "_full", 0, params.lightCount, pAll, seed++);
        checkTable(kernel, mode + "_delta", params.deltaTableOffset, params.deltaCount, pDelta, seed++);
        checkTable(kernel, mode + "_continuous", params.continuousTableOffset, params.continuousCount, pContinuous,
                   seed++);
    }
}

TEST(LightSelection, MeshTrianglesByArea) {
    // The mesh light's triangles (areas 0.5, 0.005, 0.5) through sampleAlias on meshTable.
    const Scene scene = selectionScene(LightSelection::Power);
    const SceneArrays a = buildSceneArrays(scene);
    const gpu::Light* mesh = nullptr;
    for (const auto& l : a.lights)
        if (l.type == gpu::LIGHT_MESH) mesh = &l;
    ASSERT_NE(mesh, nullptr);
    ASSERT_EQ(mesh->count, 3u);
    // Leaf-order primitive -> area, from the primitives themselves.
    std::vector<double> pmf(a.bvh.primitives.size(), 0.0);
    double total = 0.0;
    for (size_t i = 0; i < a.bvh.primitives.size(); ++i) {
        const auto& p = a.bvh.primitives[i];
        if ((p.typeAndNormals & gpu::PRIM_TYPE_MASK) != gpu::PRIM_TRIANGLE) continue;
        pmf[i] = 0.5 * glm::length(glm::cross(glm::dvec3(p.p1 - p.p0), glm::dvec3(p.p2 - p.p0)));
        total += pmf[i];
    }
    EXPECT_NEAR(mesh->area, total, 1e-6 * total);
    for (double& p : pmf) p /= total;
    test::LightKernel kernel(a);
    checkTable(kernel, "mesh_triangles", mesh->first, mesh->count, pmf, 710, gpu::LIGHT_TEST_TABLE_MESH);
}

// ---- Alias tables on the CPU ------------------------------------------------------------------------

namespace {

// The probability of each slot's item as the GLSL sampler draws it: slot i with 1/n, kept
// with its probability, else its alias.
std::vector<double> enumerate(const std::vector<gpu::AliasEntry>& table) {
    const double n = double(table.size());
    std::vector<double> p(table.size(), 0.0);
    for (size_t i = 0; i < table.size(); ++i) {
        p[i] += table[i].probability / n;
        p[table[i].alias] += (1.0 - double(table[i].probability)) / n;
    }
    return p;
}

}  // namespace

TEST(AliasTable, EnumerationReproducesTheWeights) {
    // Each slot's probability is a float: enumeration is exact to n * 2^-24 / n = 2^-24 per
    // slot that feeds an item, i.e. to 1e-6 absolute at most for these sizes.
    std::mt19937 rng(7);
    std::vector<std::vector<double>> cases = {
        {1.0}, {1.0, 3.0}, {1.0, 0.0, 3.0, 0.5, 0.0, 1e-6, 7.0}, {0.0, 0.0, 5.0}, {1e-9, 1.0, 1e9}};
    for (int k = 0; k < 20; ++k) {  // random sizes, with zeros and a wide range of magnitudes
        std::vector<double> w(1 + rng() % 300);
        for (double& x : w) x = (rng() % 4 == 0) ? 0.0 : std::exp(std::uniform_real_distribution<double>(-12, 12)(rng));
        cases.push_back(w);
    }
    for (size_t c = 0; c < cases.size(); ++c) {
        const auto& w = cases[c];
        double sum = 0.0;
        for (double x : w) sum += x;
        if (!(sum > 0.0)) continue;
        std::vector<uint32_t> items(w.size());
        for (size_t i = 0; i < items.size(); ++i) items[i] = uint32_t(100 + i);
        const auto table = buildAliasTable(w, items);
        ASSERT_EQ(table.size(), w.size());
        const auto p = enumerate(table);
        for (size_t i = 0; i < w.size(); ++i) {
            SCOPED_TRACE("case " + std::to_string(c) + " entry " + std::to_string(i));
            EXPECT_EQ(table[i].item, items[i]);
            EXPECT_LT(table[i].alias, table.size());
            EXPECT_GE(table[i].probability, 0.0f);
            EXPECT_LE(table[i].probability, 1.0f);
            EXPECT_EQ(table[i].pmf, float(w[i] / sum));
            EXPECT_NEAR(p[i], w[i] / sum, 1e-6);
            // A zero weight is never drawn: its slot always defers to its alias, and no slot
            // defers to it.
            if (w[i] == 0.0) {
                EXPECT_EQ(p[i], 0.0);
            }
        }
    }
}

TEST(AliasTable, AllZeroWeightsGiveUniform) {
    for (size_t n : {1u, 2u, 5u, 64u}) {
        const auto table = buildAliasTable(std::vector<double>(n, 0.0), std::vector<uint32_t>(n, 3u));
        const auto p = enumerate(table);
        for (size_t i = 0; i < n; ++i) {
            EXPECT_EQ(table[i].pmf, float(1.0 / n));
            EXPECT_NEAR(p[i], 1.0 / n, 1e-7);
        }
    }
    EXPECT_TRUE(buildAliasTable({}, {}).empty());
}
