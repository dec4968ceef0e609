// JSON scene loading: a scene using every field converts to the expected values (power to
// radiance worked by hand below), omitted fields take SCENE_FORMAT.md's defaults, and each
// class of bad input gives a one-line InputError naming the file and the JSON path.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "scene/integrator_json.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using penumbra::test::freshTempDir;
using penumbra::test::loadError;
using penumbra::test::writeFile;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

void expectVec(glm::vec3 actual, glm::vec3 expected, float tolerance = 1e-5f) {
    EXPECT_NEAR(actual.x, expected.x, tolerance);
    EXPECT_NEAR(actual.y, expected.y, tolerance);
    EXPECT_NEAR(actual.z, expected.z, tolerance);
}

// Every section and field of the format. Expected conversions:
//   sphere r = 0.5, P = 10:            Le = P/(4 pi^2 r^2) = 10/pi^2        = 1.0132118
//   quad 2 x 1 (area 2), P = 4 pi:     Le = P/(pi A)       = 4 pi/(2 pi)    = 2
//   same quad two-sided:               Le = P/(2 pi A)                      = 1
//   triangle area 0.5, P = [pi,2pi,0]: Le = P/(pi 0.5)                      = [2, 4, 0]
//   point light P = 4 pi:              I  = P/(4 pi)                        = 1
const char* kFullScene = R"({
  "camera": { "eye": [1, 2, 6], "target": [0, 1, 0], "up": [0, 1, 0], "fov_y": 35 },
  "film": { "width": 640, "height": 480 },
  "sampler": { "spp": 4, "seed": 7, "sample_offset": 100, "type": "independent" },
  "integrator": { "type": "direct", "strategy": "bsdf", "light_samples": 2 },
  "materials": {
    "shiny": { "type": "phong", "kd": [0.3, 0.3, 0.3], "ks": [0.6, 0.6, 0.6], "exponent": 50 },
    "grey": { "type": "diffuse", "albedo": 0.25 }
  },
  "shapes": [
    { "type": "sphere", "center": [0, 1, 0], "radius": 0.5, "material": "shiny", "power": 10 },
    { "type": "quad", "origin": [0, 3, 0], "edge_u": [2, 0, 0], "edge_v": [0, 0, 1], "power": 12.566370614359172 },
    { "type": "quad", "origin": [0, 3, 0], "edge_u": [2, 0, 0], "edge_v": [0, 0, 1], "power": 12.566370614359172,
      "two_sided": true },
    { "type": "mesh", "positions": [0,0,0, 1,0,0, 0,1,0], "indices": [0, 1, 2], "normals": [0,0,2, 0,0,1, 0,0,1],
      "material": "grey", "power": [3.141592653589793, 6.283185307179586, 0] },
    { "type": "sphere", "center": [3, 1, 0], "radius": 1, "emission": [1, 2, 3] }
  ],
  "lights": [
    { "type": "point", "position": [0, 5, 0], "power": 12.566370614359172 },
    { "type": "point", "position": [1, 5, 0], "intensity": [1, 2, 3] },
    { "type": "directional", "direction": [0, -2, 0], "irradiance": [1, 2, 3] },
    { "type": "environment" }
  ]
})";

}  // namespace

TEST(SceneLoad, FullSceneConvertsEveryField) {
    auto file = writeFile(freshTempDir() / "full.json", kFullScene);
    Scene s = loadScene(file);
    EXPECT_EQ(s.name, "full");
    EXPECT_EQ(s.path, file.string());
    expectVec(s.camera.eye, {1, 2, 6});
    EXPECT_FLOAT_EQ(s.camera.fovY, 35.0f);
    EXPECT_EQ(s.film.width, 640u);
    EXPECT_EQ(s.film.height, 480u);
    EXPECT_EQ(s.sampler.spp, 4u);
    EXPECT_EQ(s.sampler.seed, 7u);
    EXPECT_EQ(s.sampler.sampleOffset, 100u);
    EXPECT_EQ(s.sampler.type, SamplerType::Independent);

    EXPECT_EQ(s.integrator.type, IntegratorType::Direct);
    EXPECT_EQ(s.integrator.strategy, Strategy::Bsdf);
    EXPECT_EQ(s.integrator.lightSamples, 2u);
    EXPECT_EQ(integratorJson(s.integrator)["strategy"], "bsdf");
    EXPECT_EQ(integratorJson(s.integrator)["light_samples"], 2);
    EXPECT_EQ(integratorJson(s.integrator)["heuristic"], "power");  // default filled in
    EXPECT_EQ(integratorJson(s.integrator).size(), 7u);

    // materials[0] is the default; named materials follow (in name order).
    ASSERT_EQ(s.materials.size(), 3u);
    expectVec(s.materials[0].kd, glm::vec3(0.8f));
    const Material& grey = s.materials[1];
    const Material& shiny = s.materials[2];
    EXPECT_EQ(grey.name, "grey");
    expectVec(grey.kd, glm::vec3(0.25f));  // a single number is grey
    EXPECT_EQ(shiny.type, MaterialType::Phong);
    expectVec(shiny.ks, glm::vec3(0.6f));
    EXPECT_FLOAT_EQ(shiny.exponent, 50.0f);

    ASSERT_EQ(s.shapes.size(), 5u);
    EXPECT_EQ(s.shapes[0].type, ShapeType::Sphere);
    EXPECT_EQ(s.shapes[0].material, 2u);
    expectVec(s.shapes[0].emission, glm::vec3(1.0132118f));
    EXPECT_EQ(s.shapes[1].type, ShapeType::Quad);
    EXPECT_EQ(s.shapes[1].material, 0u);
    expectVec(s.shapes[1].emission, glm::vec3(2.0f));
    EXPECT_TRUE(s.shapes[2].twoSided);
    expectVec(s.shapes[2].emission, glm::vec3(1.0f));
    EXPECT_EQ(s.shapes[3].type, ShapeType::Mesh);
    EXPECT_EQ(s.shapes[3].material, 1u);
    expectVec(s.shapes[3].emission, {2, 4, 0});
    ASSERT_EQ(s.shapes[3].normals.size(), 3u);
    expectVec(s.shapes[3].normals[0], {0, 0, 1});  // normalized
    expectVec(s.shapes[4].emission, {1, 2, 3});

    ASSERT_EQ(s.lights.size(), 4u);
    EXPECT_EQ(s.lights[0].type, LightType::Point);
    expectVec(s.lights[0].intensity, glm::vec3(1.0f));
    expectVec(s.lights[1].intensity, {1, 2, 3});
    EXPECT_EQ(s.lights[2].type, LightType::Directional);
    expectVec(s.lights[2].direction, {0, -1, 0});
    expectVec(s.lights[2].intensity, {1, 2, 3});
    EXPECT_EQ(s.lights[3].type, LightType::Environment);
    expectVec(s.lights[3].intensity, glm::vec3(1.0f));
    EXPECT_TRUE(s.notes.empty());
}

TEST(SceneLoad, EmptySceneTakesDefaults) {
    Scene s = loadScene(writeFile(freshTempDir() / "empty.json", "{}"));
    expectVec(s.camera.eye, {0, 1, 5});
    expectVec(s.camera.target, {0, 1, 0});
    EXPECT_FLOAT_EQ(s.camera.fovY, 40.0f);
    EXPECT_EQ(s.film.width, 512u);
    EXPECT_EQ(s.film.height, 512u);
    EXPECT_EQ(s.sampler.spp, 16u);
    EXPECT_EQ(s.sampler.type, SamplerType::Sobol);
    EXPECT_EQ(s.integrator.type, IntegratorType::Direct);
    EXPECT_EQ(s.integrator.strategy, Strategy::Mis);
    EXPECT_EQ(s.integrator.sphereSampling, SphereSampling::SolidAngle);
    EXPECT_EQ(s.integrator.lightSelection, LightSelection::Power);
    nlohmann::json expected = {{"type", "direct"},   {"strategy", "mis"},   {"heuristic", "power"},
                               {"light_samples", 1}, {"bsdf_samples", 1},   {"sphere_sampling", "solid_angle"},
                               {"light_selection", "power"}};
    EXPECT_EQ(integratorJson(s.integrator), expected);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_TRUE(s.shapes.empty());
    EXPECT_TRUE(s.lights.empty());
}

TEST(SceneLoad, AoIntegratorAndPhongDefaults) {
    Scene s = loadScene(writeFile(freshTempDir() / "ao.json", R"({
      "integrator": {"type": "ao", "sampling": "uniform"},
      "materials": {"p": {"type": "phong"}}})"));
    EXPECT_EQ(s.integrator.type, IntegratorType::AmbientOcclusion);
    EXPECT_EQ(s.integrator.aoSampling, AoSampling::Uniform);
    EXPECT_FLOAT_EQ(s.integrator.aoMaxDistance, 1e30f);
    EXPECT_EQ(integratorJson(s.integrator),
              (nlohmann::json{{"type", "ao"}, {"sampling", "uniform"}, {"max_distance", 1e30}}));
    expectVec(s.materials[1].kd, glm::vec3(0.5f));
    expectVec(s.materials[1].ks, glm::vec3(0.5f));
    EXPECT_FLOAT_EQ(s.materials[1].exponent, 20.0f);
}

TEST(SceneLoad, UnknownMaterialMessageIsExact) {
    auto file = writeFile(freshTempDir() / "cornell.json", R"({"materials": {"floor": {}},
      "shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "floor"},
                 {"type": "sphere", "center": [0,0,0], "radius": 1, "material": "flor"}]})");
    EXPECT_EQ(loadError(file), file.string() + ": shapes[1].material: unknown material \"flor\"");
}

TEST(SceneLoad, TruncatedJsonGivesLineAndColumn) {
    auto file = writeFile(freshTempDir() / "bad.json", "{\n  \"film\": {\n    \"width\": 5,\n");
    // The input ends after three lines: the parser stops at line 4, column 1.
    EXPECT_EQ(loadError(file).rfind(file.string() + ": line 4, column 1: syntax error", 0), 0u) << loadError(file);
}

TEST(SceneLoad, MissingFile) {
    auto file = freshTempDir() / "nowhere.json";
    EXPECT_EQ(loadError(file), file.string() + ": cannot open file (no such file)");
}

// One bad input per case: the message must name the file and contain `expected` (the
// JSON path and the reason).
struct BadCase {
    const char* name;
    const char* json;
    const char* expected;
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class SceneLoadBad : public ::testing::TestWithParam<BadCase> {};

TEST_P(SceneLoadBad, GivesOneLineErrorWithPath) {
    auto file = writeFile(freshTempDir() / "bad.json", GetParam().json);
    std::string message = loadError(file);
    EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(GetParam().expected), std::string::npos) << message;
}

#define SPHERE R"("type": "sphere", "center": [0,0,0])"
#define TRI R"("type": "mesh", "positions": [0,0,0, 1,0,0, 0,1,0])"

INSTANTIATE_TEST_SUITE_P(
    Cases, SceneLoadBad,
    ::testing::Values(
        BadCase{"NotAnObject", "[1, 2]", "expected an object, got an array"},
        BadCase{"UnknownRootKey", R"({"shape": []})", "unknown key \"shape\""},
        BadCase{"UnknownKey", R"({"film": {"width": 10, "hieght": 5}})", "film: unknown key \"hieght\""},
        BadCase{"WrongType", R"({"film": {"width": "wide"}})", "film.width: expected an integer, got a string"},
        BadCase{"NotInteger", R"({"sampler": {"spp": 2.5}})", "sampler.spp: expected an integer"},
        BadCase{"FilmTooLarge", R"({"film": {"height": 20000}})", "film.height: must be an integer in [1, 16384]"},
        BadCase{"ZeroSpp", R"({"sampler": {"spp": 0}})", "sampler.spp: must be an integer in [1, "},
        BadCase{"NegativeSeed", R"({"sampler": {"seed": -1}})", "sampler.seed: must be an integer in [0, 2147483647]"},
        BadCase{"SeedBeyondHeaderInt", R"({"sampler": {"seed": 3000000000}})", "sampler.seed: must be an integer in [0, 2147483647]"},
        BadCase{"UnknownSamplerType", R"({"sampler": {"type": "halton"}})",
                "sampler.type: \"halton\" is not one of \"sobol\", \"independent\""},
        BadCase{"SamplerTypeNotString", R"({"sampler": {"type": 1}})", "sampler.type: expected a string, got a number"},
        BadCase{"MissingRequired", "{\"shapes\": [{" SPHERE "}]}", "shapes[0]: missing required field \"radius\""},
        BadCase{"MissingType", R"({"shapes": [{"radius": 1}]})", "shapes[0]: missing required field \"type\""},
        BadCase{"UnknownShapeType", R"({"shapes": [{"type": "cube"}]})", "shapes[0].type: \"cube\" is not one of"},
        BadCase{"InfiniteLiteral", R"({"camera": {"fov_y": 1e999}})", "camera.fov_y: number is not finite"},
        BadCase{"InfiniteInArray", R"({"shapes": [{"type": "sphere"}, {"center": [0, -1e999]}]})",
                "shapes[1].center[1]: number is not finite"},
        BadCase{"TooLargeForFloat", R"({"camera": {"eye": [0, 1e300, 0]}})", "camera.eye[1]: number is not finite"},
        BadCase{"NegativeRadius", "{\"shapes\": [{" SPHERE ", \"radius\": -1}]}", "shapes[0].radius: must be > 0"},
        BadCase{"ZeroAreaQuad",
                R"({"shapes": [{"type": "quad", "origin": [0,0,0], "edge_u": [1,0,0], "edge_v": [2,0,0]}]})",
                "shapes[0]: quad has zero or non-finite area"},
        BadCase{"ZeroAreaTriangle",
                R"({"shapes": [{"type": "mesh", "positions": [0,0,0, 1,1,1, 2,2,2], "indices": [0,1,2]}]})",
                "shapes[0].indices: triangle 0 has zero or non-finite area"},
        BadCase{"IndexOutOfRange", "{\"shapes\": [{" TRI ", \"indices\": [0, 1, 3]}]}",
                "shapes[0].indices[2]: index 3 out of range (3 vertices)"},
        BadCase{"NegativeIndex", "{\"shapes\": [{" TRI ", \"indices\": [0, -1, 2]}]}", "shapes[0].indices[1]: must be"},
        BadCase{"IndicesNotTriples", "{\"shapes\": [{" TRI ", \"indices\": [0, 1]}]}",
                "shapes[0].indices: length 2 is not a multiple of 3"},
        BadCase{"PositionsNotTriples", R"({"shapes": [{"type": "mesh", "positions": [0,0], "indices": [0,0,0]}]})",
                "shapes[0].positions: length 2 is not a multiple of 3"},
        BadCase{"NormalsCount", "{\"shapes\": [{" TRI ", \"indices\": [0,1,2], \"normals\": [0,0,1]}]}",
                "shapes[0].normals: has 3 numbers, positions has 9"},
        BadCase{"EmissionAndPower", "{\"shapes\": [{" SPHERE ", \"radius\": 1, \"emission\": 1, \"power\": 1}]}",
                "shapes[0]: has both \"emission\" and \"power\""},
        BadCase{"NegativePower", "{\"shapes\": [{" SPHERE ", \"radius\": 1, \"power\": [1, -1, 1]}]}",
                "shapes[0].power: must not be negative"},
        BadCase{"TwoSidedSphere", "{\"shapes\": [{" SPHERE ", \"radius\": 1, \"two_sided\": true}]}",
                "shapes[0]: unknown key \"two_sided\""},
        BadCase{"KdPlusKs", R"({"materials": {"hot": {"type": "phong", "kd": [0.5,0.5,0.5], "ks": [0.2,0.6,0.2]}}})",
                "materials.hot: kd + ks exceeds 1 in the green channel"},
        BadCase{"AlbedoAboveOne", R"({"materials": {"m": {"albedo": [1.2, 0, 0]}}})",
                "materials.m.albedo: components must be in [0, 1]"},
        BadCase{"NegativeExponent", R"({"materials": {"m": {"type": "phong", "exponent": -1}}})",
                "materials.m.exponent: must be >= 0"},
        BadCase{"FovTooWide", R"({"camera": {"fov_y": 180}})", "camera.fov_y: must be in (0, 180) degrees"},
        BadCase{"EyeIsTarget", R"({"camera": {"eye": [1,1,1], "target": [1,1,1]}})", "camera.target: must differ from eye"},
        BadCase{"UpAlongView", R"({"camera": {"eye": [0,5,0], "target": [0,0,0]}})", "camera.up: must be non-zero and not parallel"},
        BadCase{"AoOptionOnDirect", R"({"integrator": {"type": "direct", "sampling": "cosine"}})",
                "integrator: unknown key \"sampling\""},
        BadCase{"BadStrategy", R"({"integrator": {"strategy": "magic"}})", "integrator.strategy: \"magic\" is not one of"},
        BadCase{"NoSamples", R"({"integrator": {"strategy": "light", "light_samples": 0}})", "integrator: the strategy takes no samples"},
        BadCase{"PointPowerAndIntensity", R"({"lights": [{"type": "point", "position": [0,0,0], "power": 1, "intensity": 1}]})",
                "lights[0]: give exactly one of \"power\""},
        BadCase{"ZeroDirection", R"({"lights": [{"type": "directional", "direction": [0,0,0], "irradiance": 1}]})",
                "lights[0].direction: must be a non-zero vector"},
        BadCase{"TwoEnvironments", R"({"lights": [{"type": "environment"}, {"type": "environment"}]})",
                "lights[1]: only one environment light is allowed"},
        BadCase{"MissingGltf", R"({"shapes": [{"type": "gltf", "file": "missing.glb"}]})",
                "shapes[0].file: cannot open"}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return std::string(info.param.name); });

// The example scenes shipped in scenes/ load without errors or notes.
TEST(SceneLoad, ExampleScenesLoad) {
    std::filesystem::path dir = std::filesystem::path(PENUMBRA_SOURCE_DIR) / "scenes";
    Scene ao = loadScene(dir / "default.json");
    EXPECT_EQ(ao.integrator.type, IntegratorType::AmbientOcclusion);
    EXPECT_EQ(ao.film.width, 512u);
    EXPECT_EQ(ao.film.height, 384u);
    EXPECT_EQ(ao.sampler.spp, 64u);
    EXPECT_TRUE(ao.notes.empty());

    Scene model = loadScene(dir / "gltf_model.json");
    EXPECT_EQ(model.integrator.type, IntegratorType::Direct);
    EXPECT_TRUE(model.notes.empty());
    size_t triangles = 0, emitters = 0;
    for (const Shape& s : model.shapes) {
        triangles += s.indices.size() / 3;
        emitters += s.isEmitter();
    }
    EXPECT_EQ(triangles, 8192u);
    EXPECT_EQ(emitters, 1u);
    ASSERT_EQ(model.lights.size(), 1u);

    // The binary copy of the model is the same geometry.
    Scene glb = loadScene(dir / "models" / "torus_knot.glb");
    ASSERT_EQ(glb.shapes.size(), 1u);
    EXPECT_EQ(glb.shapes[0].indices.size(), 3u * 8192u);
}

// quad_sampling and triangle_sampling (SCENE_FORMAT.md v2): defaults, values, the header's
// integrator object (which lists them when given: docs/design/contract-decisions.md), bad values.
TEST(SceneLoad, PolygonSamplingOptions) {
    Scene none = loadScene(writeFile(freshTempDir() / "none.json", "{}"));
    EXPECT_EQ(none.integrator.quadSampling, QuadSampling::SolidAngle);
    EXPECT_EQ(none.integrator.triangleSampling, TriangleSampling::Area);
    EXPECT_FALSE(integratorJson(none.integrator).contains("quad_sampling"));

    Scene set = loadScene(writeFile(freshTempDir() / "set.json", R"({
      "integrator": {"quad_sampling": "area", "triangle_sampling": "solid_angle"}})"));
    EXPECT_EQ(set.integrator.quadSampling, QuadSampling::Area);
    EXPECT_EQ(set.integrator.triangleSampling, TriangleSampling::SolidAngle);
    EXPECT_EQ(integratorJson(set.integrator)["quad_sampling"], "area");
    EXPECT_EQ(integratorJson(set.integrator)["triangle_sampling"], "solid_angle");

    auto bad = writeFile(freshTempDir() / "bad.json", R"({"integrator": {"quad_sampling": "cap"}})");
    EXPECT_EQ(loadError(bad).rfind(bad.string() + ": integrator.quad_sampling: ", 0), 0u) << loadError(bad);
    auto ao = writeFile(freshTempDir() / "ao.json", R"({"integrator": {"type": "ao", "triangle_sampling": "area"}})");
    EXPECT_NE(loadError(ao).find("triangle_sampling"), std::string::npos) << loadError(ao);
}
