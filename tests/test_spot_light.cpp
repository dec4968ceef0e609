// Spot lights as input (SCENE_FORMAT.md `spot`, glTF KHR_lights_punctual `spot`): the values
// a scene or glTF file gives become the right light, light selection weighs a spot by its
// power 2 pi I ((1 - cos inner) + (cos inner - cos outer) / 3), a glTF file with a spot
// renders it, and bad cones or missing fields are one-line input errors with exit status 2.
// The spot's radiometry under every strategy is in test_direct.cpp (closed forms).
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "gltf_builder.h"
#include "gpu_fixture.h"
#include "render/light_arrays.h"
#include "render/scene_arrays.h"
#include "render_helpers.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;
using test::freshTempDir;
using test::GltfBuilder;
using test::loadError;
using test::writeFile;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = std::numbers::pi;

json sceneWithLights(json lights) {
    return {{"shapes", {{{"type", "quad"}, {"origin", {-1, 0, -1}}, {"edge_u", {0, 0, 2}}, {"edge_v", {2, 0, 0}}}}},
            {"lights", lights}};
}

json spot(const json& extra) {
    json j = {{"type", "spot"}, {"position", {0, 1, 0}}, {"direction", {0, -1, 0}}, {"intensity", 1}};
    j.update(extra);
    return j;
}

// A glTF file with one triangle and one spot light (node rotated -90 degrees about +X:
// its -Z points down -Y), with the given `spot` object.
std::string gltfWithSpot(const json& spotObject, double intensity = 3.0) {
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    json light = {{"type", "spot"}, {"intensity", intensity}};
    if (!spotObject.is_null()) light["spot"] = spotObject;
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {light};
    double h = std::sqrt(0.5);
    b.addNode({{"translation", {0, 2, 0}},
               {"rotation", {-h, 0, 0, h}},
               {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    return b.gltf();
}

}  // namespace

TEST(SpotLight, JsonFieldsDefaultsAndPowerConversion) {
    json doc = sceneWithLights({spot({{"inner_angle", 10}, {"outer_angle", 30}, {"direction", {0, -2, 0}}}),
                                spot({{"intensity", nullptr}}), spot({{"power", 2}})});
    doc["lights"][1].erase("intensity");
    doc["lights"][1]["power"] = 3;
    doc["lights"][2].erase("intensity");
    Scene s = test::sceneFromJson(doc, "spot-fields");
    ASSERT_EQ(s.lights.size(), 3u);
    EXPECT_EQ(s.lights[0].type, LightType::Spot);
    EXPECT_NEAR(s.lights[0].direction.y, -1.0, 1e-7);  // normalized
    EXPECT_NEAR(s.lights[0].cosInner, std::cos(10 * kPi / 180), 1e-7);
    EXPECT_NEAR(s.lights[0].cosOuter, std::cos(30 * kPi / 180), 1e-7);
    // Defaults inner 0, outer 45: P = 2 pi I (1 - cos 45) / 3.
    EXPECT_NEAR(s.lights[1].cosInner, 1.0, 1e-7);
    EXPECT_NEAR(s.lights[1].cosOuter, std::sqrt(0.5), 1e-7);
    EXPECT_NEAR(s.lights[1].intensity.x, 3.0 / (2 * kPi * (1 - std::sqrt(0.5)) / 3), 1e-5);
    EXPECT_NEAR(s.lights[2].intensity.x, 2.0 / (2 * kPi * (1 - std::sqrt(0.5)) / 3), 1e-5);
}

TEST(SpotLight, SelectedInProportionToItsPowerAndSampledAsADeltaLight) {
    // A spot (inner 20, outer 50, I = 4) and a point light (I = 1, power 4 pi).
    json doc = sceneWithLights({spot({{"inner_angle", 20}, {"outer_angle", 50}, {"intensity", 4}}),
                                {{"type", "point"}, {"position", {0, 2, 0}}, {"intensity", 1}}});
    Scene scene = test::sceneFromJson(doc, "spot-selection");
    SceneArrays arrays = buildSceneArrays(scene);
    ASSERT_EQ(arrays.lights.size(), 2u);
    double ci = std::cos(20 * kPi / 180), co = std::cos(50 * kPi / 180);
    double spotPower = 2 * kPi * 4 * ((1 - ci) + (ci - co) / 3), pointPower = 4 * kPi;
    EXPECT_NEAR(arrays.lights[0].selectionProb, spotPower / (spotPower + pointPower), 1e-6);
    EXPECT_NEAR(arrays.lights[1].selectionProb, pointPower / (spotPower + pointPower), 1e-6);
    EXPECT_TRUE(isDeltaLight(arrays.lights[0].type));
    EXPECT_EQ(arrays.deltaCount, 2u);  // both in the delta-only table
    EXPECT_EQ(arrays.continuousCount, 0u);
}

struct BadSpot {
    const char* name;
    json extra;
    const char* mustMention;
};

class SpotLightBadJson : public ::testing::TestWithParam<BadSpot> {};

TEST_P(SpotLightBadJson, IsAnInputErrorNamingThePath) {
    json light = spot(GetParam().extra);
    for (auto it = light.begin(); it != light.end();) it = it->is_null() ? light.erase(it) : std::next(it);
    auto file = writeFile(freshTempDir() / "bad.json", sceneWithLights({light}).dump());
    std::string message = loadError(file);
    EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(GetParam().mustMention), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, SpotLightBadJson,
    ::testing::Values(BadSpot{"InnerEqualsOuter", {{"inner_angle", 30}, {"outer_angle", 30}}, "lights[0].inner_angle"},
                      BadSpot{"InnerAboveOuter", {{"inner_angle", 40}, {"outer_angle", 30}}, "lights[0].inner_angle"},
                      BadSpot{"NegativeInner", {{"inner_angle", -1}}, "lights[0].inner_angle"},
                      BadSpot{"OuterAbove90", {{"outer_angle", 91}}, "lights[0].outer_angle"},
                      BadSpot{"OuterZero", {{"outer_angle", 0}}, "lights[0].outer_angle"},
                      BadSpot{"ZeroDirection", {{"direction", {0, 0, 0}}}, "lights[0].direction"},
                      BadSpot{"NoIntensityNorPower", {{"intensity", nullptr}}, "exactly one of"},
                      BadSpot{"BothIntensityAndPower", {{"power", 3}}, "exactly one of"},
                      BadSpot{"NegativeIntensity", {{"intensity", -1}}, "lights[0].intensity"},
                      BadSpot{"UnknownKey", {{"cone", 3}}, "unknown key \"cone\""}),
    [](const ::testing::TestParamInfo<BadSpot>& info) { return std::string(info.param.name); });

TEST(SpotLight, GltfSpotLoadsWithConeAnglesInRadians) {
    Scene s = loadScene(
        writeFile(freshTempDir() / "spot.gltf", gltfWithSpot({{"innerConeAngle", 0.2}, {"outerConeAngle", 0.7}})));
    ASSERT_EQ(s.lights.size(), 1u);  // and no environment fallback
    EXPECT_EQ(s.lights[0].type, LightType::Spot);
    EXPECT_NEAR(s.lights[0].position.y, 2.0, 1e-6);
    EXPECT_NEAR(s.lights[0].direction.y, -1.0, 1e-6);
    EXPECT_NEAR(s.lights[0].cosInner, std::cos(0.2), 1e-7);
    EXPECT_NEAR(s.lights[0].cosOuter, std::cos(0.7), 1e-7);
    EXPECT_NEAR(s.lights[0].intensity.x, 3.0, 1e-6);  // candela read as W/sr
    // An empty `spot` object (the extension requires one for a spot): glTF's defaults, inner 0
    // and outer pi/4.
    Scene d = loadScene(writeFile(freshTempDir() / "default.gltf", gltfWithSpot(json::object())));
    ASSERT_EQ(d.lights.size(), 1u);
    EXPECT_NEAR(d.lights[0].cosInner, 1.0, 1e-7);
    EXPECT_NEAR(d.lights[0].cosOuter, std::sqrt(0.5), 1e-7);
}

TEST(SpotLight, GltfBadConesExitTwoWithOneLineAndNothingWritten) {
    struct Case {
        const char* name;
        json spotObject;
        const char* mustMention;
    };
    const Case cases[] = {
        {"outer-below-inner", {{"innerConeAngle", 0.6}, {"outerConeAngle", 0.5}}, "spot.innerConeAngle"},
        {"outer-equals-inner", {{"innerConeAngle", 0.5}, {"outerConeAngle", 0.5}}, "spot.innerConeAngle"},
        {"outer-above-90", {{"outerConeAngle", 1.6}}, "spot.outerConeAngle"},
        {"outer-zero", {{"innerConeAngle", 0.0}, {"outerConeAngle", 0.0}}, "spot.outerConeAngle"},
        {"inner-negative", {{"innerConeAngle", -0.1}, {"outerConeAngle", 0.5}}, "spot.innerConeAngle"},
    };
    for (const Case& c : cases) {
        fs::path dir = freshTempDir();
        fs::path file = writeFile(dir / (std::string(c.name) + ".gltf"), gltfWithSpot(c.spotObject));
        fs::path out = dir / "out.exr";
        std::string err;
        int status = test::runPenumbra("render '" + file.string() + "' -o '" + out.string() + "' --quiet", &err);
        EXPECT_EQ(status, 2) << c.name << ": " << err;
        EXPECT_NE(err.find(file.string()), std::string::npos) << c.name << ": " << err;
        EXPECT_NE(err.find(c.mustMention), std::string::npos) << c.name << ": " << err;
        ASSERT_FALSE(err.empty());
        EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line: " << err;
        EXPECT_FALSE(fs::exists(out)) << c.name;
    }
}

TEST(SpotLight, GltfSpotRendersItsConeOnTheFloor) {
    // The spot 2 above a floor, pointing down, outer cone 0.5 rad: the floor is lit inside a
    // disk of radius 2 tan(0.5) = 1.09 and black outside it (no other light).
    GltfBuilder b;
    b.addMeshNode({{"attributes", {{"POSITION", b.positions({-3, 0, -3, -3, 0, 3, 3, 0, 3, 3, 0, -3})}}},
                   {"indices", b.indices({0, 1, 2, 0, 2, 3})}});
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "spot"}, {"intensity", 10}, {"spot", {{"innerConeAngle", 0.3}, {"outerConeAngle", 0.5}}}}};
    double h = std::sqrt(0.5);
    b.addNode({{"translation", {0, 2, 0}},
               {"rotation", {-h, 0, 0, h}},
               {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    // Beside the scene file sceneFromJson writes (a scene reads files in its own folder only).
    fs::path model = writeFile(test::outputPath("gltf-spot.gltf"), b.gltf());
    json doc = {{"camera", test::topDownCamera(0.0, 0.0, 2.5)},
                {"film", {{"width", 32}, {"height", 32}}},
                {"sampler", {{"spp", 4}, {"seed", 1}}},
                {"shapes", {{{"type", "gltf"}, {"file", model.filename().string()}}}}};
    Scene scene = test::sceneFromJson(doc, "gltf-spot");
    Image image = test::renderScene(scene);
    // Centre pixel: lit; corners (3.5 from the axis): black.
    auto at = [&](int x, int y) { return image.rgb[3 * (size_t(y) * 32 + x)]; };
    EXPECT_GT(at(16, 16), 0.1f);
    EXPECT_EQ(at(0, 0), 0.0f);
    EXPECT_EQ(at(31, 31), 0.0f);
}
