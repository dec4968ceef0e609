// Groups and instances (SCENE_FORMAT.md "Mesh files, transforms and instances"): what an
// instance's copy is after loading (instance o shape, the material it names, emitters that
// stay emitters), renders of instanced lights and surfaces against the closed forms of
// tests/render_helpers.h and against the same shapes written out, and every bad group or
// instance refused with its JSON path.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "image/image.h"
#include "many_light_scenes.h"
#include "render/scene_arrays.h"
#include "render_helpers.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr double kAlbedo = 0.6;
constexpr double kAlpha = 1e-3;

Scene loadDoc(const json& doc, const std::vector<Override>& overrides = {}) {
    const fs::path file = test::freshTempDir() / "scene.json";
    test::writeFile(file, doc.dump());
    return loadScene(file, overrides);
}

std::string loadDocError(const json& doc) {
    const fs::path file = test::freshTempDir() / "scene.json";
    test::writeFile(file, doc.dump());
    return test::loadError(file);
}

// A list of one shape, as a brace list of one json value gives that value itself.
json listOf(const json& shapes) { return shapes.is_array() ? shapes : json::array({shapes}); }

json withShapes(const json& shapes) {
    return {{"materials",
             {{"a", {{"type", "diffuse"}, {"albedo", 0.1}}},
              {"b", {{"type", "diffuse"}, {"albedo", 0.2}}},
              {"c", {{"type", "diffuse"}, {"albedo", 0.3}}}}},
            {"shapes", listOf(shapes)},
            {"lights", {{{"type", "point"}, {"position", {0, 5, 0}}, {"power", 10}}}}};
}

void expectNear(glm::vec3 got, glm::dvec3 want, const std::string& what) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-5) << what << "[" << c << "]";
}

const json kUnitQuad = {{"type", "quad"}, {"origin", {0, 0, 0}}, {"edge_u", {1, 0, 0}}, {"edge_v", {0, 0, 1}}};

json group(const std::string& name, const json& shapes) {
    return {{"type", "group"}, {"name", name}, {"shapes", listOf(shapes)}};
}
json instance(const std::string& of, const json& toWorld = nullptr) {
    json i = {{"type", "instance"}, {"of", of}};
    if (!toWorld.is_null()) i["to_world"] = toWorld;
    return i;
}

// The direct integrator with each strategy that weighs light and BRDF samples differently.
std::vector<json> strategies() {
    std::vector<json> out;
    for (const char* s : {"light", "bsdf", "mis", "mixture", "ris"})
        out.push_back({{"type", "direct"}, {"strategy", s}});
    return out;
}

}  // namespace

TEST(InstancesLoad, TheInstanceMapComesAfterTheShapesOwn) {
    // The group's quad is scaled by 2 (its own to_world); the instance turns it a quarter
    // about +y and moves it: p -> R(2 p) + t. An emitting quad is copied, moved by both; a
    // plain one stays in the group's frame (scaled by its own map only) and the instance
    // keeps R and t.
    json quad = kUnitQuad;
    quad["to_world"] = {{"scale", 2}};
    json inst = instance("g", {{"rotate", {{"axis", {0, 1, 0}}, {"angle", 90}}}, {"translate", {1, 2, 3}}});
    // A quarter turn about +y takes x to -z and z to x.
    auto turn = [](glm::dvec3 p) { return glm::dvec3(p.z, p.y, -p.x); };
    auto map = [&](glm::dvec3 p) { return turn(2.0 * p) + glm::dvec3(1, 2, 3); };
    json lamp = quad;
    lamp["emission"] = 1;
    const Scene copied = loadDoc(withShapes({group("g", {lamp}), inst}));
    ASSERT_EQ(copied.shapes.size(), 1u);
    const Shape& q = copied.shapes[0];
    expectNear(q.origin, map({0, 0, 0}), "origin");
    expectNear(q.origin + q.edgeU, map({1, 0, 0}), "origin + edge_u");
    expectNear(q.origin + q.edgeV, map({0, 0, 1}), "origin + edge_v");

    const Scene traced = loadDoc(withShapes({group("g", {quad}), inst}));
    EXPECT_TRUE(traced.shapes.empty());
    ASSERT_EQ(traced.instancedGroups.size(), 1u);
    ASSERT_EQ(traced.instances.size(), 1u);
    const Shape& own = traced.instancedGroups[0].shapes.at(0);
    expectNear(own.edgeU, {2, 0, 0}, "the group's edge_u");
    const Instance& i = traced.instances[0];
    for (glm::dvec3 p : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)})
        expectNear(glm::vec3(i.linear * p + i.translation), turn(p) + glm::dvec3(1, 2, 3), "instance map");
}

TEST(InstancesLoad, EachInstanceIsAPlacementAndTheGroupAloneIsNotRendered) {
    const Scene none = loadDoc(withShapes({group("g", {kUnitQuad})}));
    EXPECT_TRUE(none.shapes.empty());
    EXPECT_TRUE(none.instances.empty());
    ASSERT_EQ(none.notes.size(), 1u);
    EXPECT_NE(none.notes[0].find("shapes[0]: group \"g\" is placed by no instance"), std::string::npos)
        << none.notes[0];
    // An instance may come before its group; three instances are three placements of one
    // group (and three copies of its emitter).
    json lamp = kUnitQuad;
    lamp["emission"] = 1;
    const Scene three = loadDoc(withShapes({instance("g", {{"translate", {0, 0, 0}}}), group("g", {kUnitQuad, lamp}),
                                            instance("g", {{"translate", {5, 0, 0}}}), instance("g")}));
    EXPECT_TRUE(three.notes.empty());
    ASSERT_EQ(three.shapes.size(), 3u);
    expectNear(three.shapes[0].origin, {0, 0, 0}, "first");
    expectNear(three.shapes[1].origin, {5, 0, 0}, "second");
    expectNear(three.shapes[2].origin, {0, 0, 0}, "third (no to_world: the identity)");
    EXPECT_EQ(three.instancedGroups.size(), 1u);
    ASSERT_EQ(three.instances.size(), 3u);
    EXPECT_EQ(three.instances[1].translation, glm::dvec3(5, 0, 0));
    EXPECT_EQ(three.instances[2].linear, glm::dmat3(1.0));
}

TEST(InstancesLoad, ASphereInstanceIsScaledAndMovedWithItsCentre) {
    json sphere = {{"type", "sphere"}, {"center", {1, 0, 0}}, {"radius", 0.5}, {"emission", 1}};
    const json toWorld = {{"scale", 2}, {"translate", {0, 3, 0}}};
    const Scene scene = loadDoc(withShapes({group("g", {sphere}), instance("g", toWorld)}));
    ASSERT_EQ(scene.shapes.size(), 1u);
    expectNear(scene.shapes[0].center, {2, 3, 0}, "center");
    EXPECT_NEAR(scene.shapes[0].radius, 1.0f, 1e-6f);
    // Traced or copied, a sphere takes a uniform scale only.
    for (bool emits : {true, false}) {
        json s = sphere;
        if (!emits) s.erase("emission");
        EXPECT_NE(loadDocError(withShapes({group("g", {s}), instance("g", {{"scale", {1, 2, 1}}})}))
                      .find("shapes[1].to_world.scale: a sphere takes only a uniform scale"),
                  std::string::npos)
            << emits;
        EXPECT_NE(loadDocError(withShapes({group("g", {s}), instance("g", {{"translate", {0, 0, 2e8}}})}))
                      .find("shapes[1].to_world: moves the sphere outside"),
                  std::string::npos)
            << emits;
    }
    json mesh = {{"type", "mesh"}, {"positions", {0, 0, 0, 1, 0, 0, 0, 1, 0}}, {"indices", {0, 1, 2}}};
    EXPECT_NE(loadDocError(withShapes({group("g", {mesh}), instance("g", {{"translate", {2e8, 0, 0}}})}))
                  .find("shapes[1].to_world: moves the mesh outside"),
              std::string::npos);
}

TEST(InstancesLoad, AnInstancesMaterialReplacesTheGroupsMaterials) {
    json qa = kUnitQuad, mb = {{"type", "mesh"}, {"positions", {0, 0, 0, 1, 0, 0, 0, 1, 0}}, {"indices", {0, 1, 2}}};
    qa["material"] = "a";
    mb["material"] = "b";
    json over = instance("g");
    over["material"] = "c";
    auto name = [](const Scene& scene, uint32_t material) { return scene.materials.at(material).name; };
    // Traced: the group keeps its materials, the instance names its own.
    const Scene traced = loadDoc(withShapes({group("g", {qa, mb}), instance("g"), over}));
    ASSERT_EQ(traced.instances.size(), 2u);
    EXPECT_EQ(traced.instances[0].material, kNoMaterialOverride);
    EXPECT_EQ(name(traced, traced.instances[1].material), "c");
    const InstancedGroup& own = traced.instancedGroups.at(traced.instances[0].group);
    ASSERT_EQ(own.shapes.size(), 2u);
    EXPECT_EQ(name(traced, own.shapes[0].material), "a");
    EXPECT_EQ(name(traced, own.shapes[1].material), "b");
    // Copied (emitters): each copy has the instance's material.
    qa["emission"] = 1;
    mb["emission"] = 1;
    const Scene copied = loadDoc(withShapes({group("g", {qa, mb}), instance("g"), over}));
    ASSERT_EQ(copied.shapes.size(), 4u);
    EXPECT_EQ(name(copied, copied.shapes[0].material), "a");
    EXPECT_EQ(name(copied, copied.shapes[1].material), "b");
    EXPECT_EQ(name(copied, copied.shapes[2].material), "c");
    EXPECT_EQ(name(copied, copied.shapes[3].material), "c");
}

TEST(InstancesLoad, EmittersStayEmittersWithTheGroupsRadiance) {
    // power 3 pi over the unit quad: Le = P / (pi A) = 3, in every copy however it is scaled.
    json light = kUnitQuad;
    light["power"] = 3 * M_PI;
    const Scene scene = loadDoc(withShapes({group("g", {light}), instance("g"), instance("g", {{"scale", 2}})}));
    ASSERT_EQ(scene.shapes.size(), 2u);
    for (const Shape& s : scene.shapes) EXPECT_NEAR(s.emission.x, 3.0f, 1e-5f);
    EXPECT_NEAR(glm::length(glm::cross(scene.shapes[1].edgeU, scene.shapes[1].edgeV)), 4.0f, 1e-5f);
}

TEST(InstancesLoad, SetReachesShapesInsideGroups) {
    json sphere = {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.5}};
    const Scene scene =
        loadDoc(withShapes({group("g", {sphere}), instance("g")}), {{"shapes[0].shapes[0].radius", "2"}});
    ASSERT_EQ(scene.instancedGroups.size(), 1u);
    EXPECT_EQ(scene.instancedGroups[0].shapes.at(0).radius, 2.0f);
}

TEST(InstancesLoad, BadGroupsAndInstancesAreRefusedWithTheJsonPath) {
    const json g = group("g", {kUnitQuad});
    struct Case {
        json shapes;
        std::string needle;
    };
    json badMaterial = instance("g");
    badMaterial["material"] = "nope";
    json extraKey = instance("g");
    extraKey["scale"] = 2;
    json groupKey = g;
    groupKey["to_world"] = {{"scale", 2}};
    const std::vector<Case> cases = {
        {{g, instance("tree")}, "shapes[1].of: no group named \"tree\" (groups: \"g\")"},
        {{instance("tree")}, "shapes[0].of: no group named \"tree\" (the scene declares no groups)"},
        {{g, group("g", {kUnitQuad})}, "shapes[1].name: a second group named \"g\""},
        {{group("e", json::array()), instance("e")}, "shapes[0].shapes: a group needs at least one shape"},
        {{group("", {kUnitQuad})}, "shapes[0].name: a group's name must not be empty"},
        {{{{"type", "group"}, {"shapes", {kUnitQuad}}}}, "shapes[0]"},
        {{group("n", {g}), instance("n")},
         "shapes[0].shapes[0].type: a group holds spheres, quads, meshes and gltf "
         "shapes, not groups"},
        {{g, group("n", {instance("g")})},
         "shapes[1].shapes[0].type: a group holds spheres, quads, meshes and gltf "
         "shapes, not instances"},
        {{g, badMaterial}, "shapes[1].material: unknown material \"nope\""},
        {{g, extraKey}, "shapes[1]"},
        {{groupKey}, "shapes[0]"},
        {{g, instance("g", {{"translate", {0, 2e8, 0}}})}, "shapes[1].to_world: moves the quad outside"},
        {{g, instance("g", "identity")}, "shapes[1].to_world: expected a 4x4 matrix"},
        {{group("g", {{{"type", "quad"}, {"origin", {0, 0, 0}}}}), instance("g")}, "shapes[0].shapes[0]"},
        {{g, {{"type", "instance"}}}, "shapes[1]"},
        {{g, {{"type", "instance"}, {"of", 3}}}, "shapes[1].of"},
    };
    for (const Case& c : cases) {
        const std::string message = loadDocError(withShapes(c.shapes));
        EXPECT_NE(message.find("scene.json: " + c.needle), std::string::npos)
            << c.shapes.dump() << "\n  got: " << message << "\n  want: " << c.needle;
    }
}

TEST(InstancesLoad, CopiesBeyondTheLimitAreRefused) {
    // 2^24 triangles would be copied by the 2^12 + 1st instance of a 4096-triangle group
    // that emits (each copy is a light; what instances trace is not copied and not counted).
    json positions = json::array(), indices = json::array();
    for (int t = 0; t < 4096; ++t) {
        positions.insert(positions.end(), {t, 0, 0, t + 1, 0, 0, t, 1, 0});
        indices.insert(indices.end(), {3 * t, 3 * t + 1, 3 * t + 2});
    }
    json shapes = {group("g", {{{"type", "mesh"}, {"positions", positions}, {"indices", indices}, {"emission", 1}}})};
    for (int i = 0; i <= 4096; ++i) shapes.push_back(instance("g"));
    EXPECT_NE(loadDocError(withShapes(shapes)).find("shapes[4097]: the instances copy more than 16777216 primitives"),
              std::string::npos);
    // Not emitting, the same group is traced, not copied: accepted, one group, 4097 instances.
    shapes[0]["shapes"][0].erase("emission");
    const Scene traced = loadDoc(withShapes(shapes));
    EXPECT_TRUE(traced.shapes.empty());
    EXPECT_EQ(traced.instancedGroups.size(), 1u);
    EXPECT_EQ(traced.instances.size(), 4097u);
}

// What an instance traces (Scene::instances) and what it copies (Scene::shapes): emitters,
// textured shapes and every shape of a scene with AOVs are copied.
TEST(InstancesLoad, EmittersTexturedShapesAndAovScenesAreCopiedTheRestTraced) {
    json lamp = kUnitQuad, plain = {{"type", "sphere"}, {"center", {1, 0, 0}}, {"radius", 0.5}, {"material", "a"}};
    lamp["emission"] = 2;
    json doc = withShapes({group("g", {lamp, plain}), instance("g", {{"scale", 2}, {"translate", {0, 3, 0}}})});
    const Scene scene = loadDoc(doc);
    ASSERT_EQ(scene.shapes.size(), 1u);
    EXPECT_TRUE(scene.shapes[0].isEmitter());
    ASSERT_EQ(scene.instancedGroups.size(), 1u);
    ASSERT_EQ(scene.instancedGroups[0].shapes.size(), 1u);
    EXPECT_EQ(scene.instancedGroups[0].shapes[0].type, ShapeType::Sphere);
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_EQ(scene.instances[0].linear, glm::dmat3(2.0));
    EXPECT_EQ(scene.instances[0].translation, glm::dvec3(0, 3, 0));
    EXPECT_EQ(scene.instances[0].material, kNoMaterialOverride);

    // Id layers number the copies; other layers are computed from the traced hit too.
    json aovs = doc;
    aovs["film"] = {{"aovs", {"albedo", "primitive_id"}}};
    const Scene copied = loadDoc(aovs);
    EXPECT_EQ(copied.shapes.size(), 2u);
    EXPECT_TRUE(copied.instances.empty());
    aovs["film"] = {{"aovs", {"albedo", "normal", "variance"}}};
    EXPECT_EQ(loadDoc(aovs).instances.size(), 1u);

    const fs::path dir = test::freshTempDir();
    writePng(dir / "t.png", Image{1, 1, {0.5f, 0.5f, 0.5f}, {}});
    json textured = doc;
    textured["materials"]["t"] = {{"type", "diffuse"}, {"albedo", {{"texture", "t.png"}}}};
    textured["shapes"][1]["material"] = "t";
    test::writeFile(dir / "scene.json", textured.dump());
    const Scene withTexture = loadScene(dir / "scene.json");
    EXPECT_EQ(withTexture.shapes.size(), 2u);
    EXPECT_TRUE(withTexture.instances.empty());
}

// An emitting quad declared in a group at the origin (facing -y) and placed by an instance
// at height h over the diffuse plane: every strategy against the polygon formula.
TEST(InstancesRender, AnInstancedQuadLightMatchesTheClosedFormUnderEveryStrategy) {
    const double Le = 5.0, h = 1.2;
    json doc = test::diffusePlaneScene(256, 7, 3.0, 1.5, kAlbedo);
    doc["shapes"].push_back(group("lamp", {{{"type", "quad"},
                                            {"origin", {-0.5, 0, -0.5}},
                                            {"edge_u", {1, 0, 0}},
                                            {"edge_v", {0, 0, 1}},
                                            {"emission", Le},
                                            {"material", "black"}}}));
    doc["shapes"].push_back(instance("lamp", {{"translate", {0, h, 0}}}));
    const std::vector<glm::dvec3> quad = {{-0.5, h, -0.5}, {0.5, h, -0.5}, {0.5, h, 0.5}, {-0.5, h, 0.5}};
    test::expectTopDownMatches(
        doc, strategies(), [&](glm::dvec3 x) { return kAlbedo / M_PI * test::polygonIrradiance(quad, x, Le); },
        "instanced-quad-light", kAlpha);
}

// The same two lamps and balls as instances and written out: the same image, bit for bit.
// Emitters are copied (one light per instance), and so is everything in a scene with an id AOV:
// the translations are exact, so the copies are the same floats as the shapes written out.
TEST(InstancesRender, CopiedInstancesRenderAsTheShapesWrittenOut) {
    const double Le = 5.0;
    const json lamp = {{"type", "quad"}, {"origin", {-0.5, 0, -0.5}}, {"edge_u", {1, 0, 0}}, {"edge_v", {0, 0, 1}},
                       {"emission", Le}, {"material", "black"}};
    const json ball = {{"type", "sphere"}, {"center", {0, 0.5, 0}}, {"radius", 0.25}, {"material", "plane"}};
    for (const char* strategy : {"light", "bsdf", "mis"}) {
        json instanced = test::diffusePlaneScene(16, 3, 0.5, 2.0, kAlbedo);
        instanced["integrator"] = {{"type", "direct"}, {"strategy", strategy}};
        instanced["film"]["aovs"] = {"shape_id"};
        json written = instanced;
        instanced["shapes"].push_back(group("lamp", {lamp, ball}));
        for (double x : {-1.0, 1.5}) {
            instanced["shapes"].push_back(instance("lamp", {{"translate", {x, 1.5, 0.25}}}));
            json q = lamp, b = ball;
            q["origin"] = {x - 0.5, 1.5, -0.25};
            b["center"] = {x, 2.0, 0.25};
            written["shapes"].push_back(q);
            written["shapes"].push_back(b);
        }
        ASSERT_TRUE(test::sceneFromJson(instanced, "instanced-lamps-load").instances.empty());
        const Image a = test::renderJson(instanced, std::string("instanced-lamps-") + strategy);
        const Image b = test::renderJson(written, std::string("written-lamps-") + strategy);
        ASSERT_EQ(a.rgb.size(), b.rgb.size());
        size_t differ = 0;
        for (size_t i = 0; i < a.rgb.size(); ++i) differ += a.rgb[i] != b.rgb[i];
        EXPECT_EQ(differ, 0u) << strategy;
        double sum = 0;
        for (float v : a.rgb) sum += v;
        EXPECT_GT(sum, 0.0) << "the lamps light the plane";
    }
}

// A sphere light declared at the origin with radius 0.2, placed scaled by 2 at height h:
// the plane sees pi Le (r/d)^2 cos(theta) of the moved sphere, r = 0.4.
TEST(InstancesRender, AScaledSphereLightInstanceMatchesTheClosedForm) {
    const double Le = 4.0, r = 0.4, h = 1.5;
    json doc = test::diffusePlaneScene(256, 5, 3.0, 1.5, kAlbedo);
    doc["shapes"].push_back(
        group("bulb",
              {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.2}, {"emission", Le}, {"material", "black"}}}));
    doc["shapes"].push_back(instance("bulb", {{"scale", 2}, {"translate", {0, h, 0}}}));
    test::expectTopDownMatches(
        doc, strategies(),
        [&](glm::dvec3 x) {
            double d2 = x.x * x.x + x.z * x.z + h * h;
            return kAlbedo / M_PI * M_PI * Le * r * r / d2 * (h / std::sqrt(d2));
        },
        "instanced-sphere-light", kAlpha);
}

// The plane itself as an instance of a grey group quad, with a brighter material of its
// own: what it reflects of a quad light is the override's albedo over pi times E.
TEST(InstancesRender, AnInstancesMaterialIsTheOneShaded) {
    const double Le = 5.0, h = 1.2, albedo = 0.9;
    json doc = test::diffusePlaneScene(256, 9, 3.0, 1.5, 0.2);
    doc["materials"]["bright"] = {{"type", "diffuse"}, {"albedo", albedo}};
    json plane = doc["shapes"][0];
    doc["shapes"] = {group("floor", {plane}),
                     {{"type", "instance"}, {"of", "floor"}, {"material", "bright"}},
                     {{"type", "quad"},
                      {"origin", {-0.5, h, -0.5}},
                      {"edge_u", {1, 0, 0}},
                      {"edge_v", {0, 0, 1}},
                      {"emission", Le},
                      {"material", "black"}}};
    const std::vector<glm::dvec3> quad = {{-0.5, h, -0.5}, {0.5, h, -0.5}, {0.5, h, 0.5}, {-0.5, h, 0.5}};
    test::expectTopDownMatches(
        doc, {{{"type", "direct"}, {"strategy", "mis"}}},
        [&](glm::dvec3 x) { return albedo / M_PI * test::polygonIrradiance(quad, x, Le); }, "instance-material",
        kAlpha);
}

// The plane as a mesh in the xy plane of its group (two triangles, vertex normals +z),
// turned onto y = 0 by its instance (-90 degrees about x: +z to +y) and stretched: the
// traced instance's points and shading normals reach the world through its maps, so the
// polygon formula holds, as for the plane written out.
TEST(InstancesRender, ATurnedMeshInstanceIsShadedWithItsMovedNormals) {
    const double Le = 5.0, h = 1.0;
    json doc = test::diffusePlaneScene(256, 13, 3.0, 1.5, kAlbedo);
    json plane = {{"type", "mesh"},
                  {"positions", {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0}},
                  {"indices", {0, 1, 2, 0, 2, 3}},
                  {"normals", {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}},
                  {"material", "plane"}};
    doc["shapes"] = {group("floor", {plane}),
                     instance("floor", {{"scale", {25, 50, 1}}, {"rotate", {{"axis", {1, 0, 0}}, {"angle", -90}}}}),
                     {{"type", "quad"},
                      {"origin", {-0.5, h, -0.5}},
                      {"edge_u", {1, 0, 0}},
                      {"edge_v", {0, 0, 1}},
                      {"emission", Le},
                      {"material", "black"}}};
    ASSERT_EQ(test::sceneFromJson(doc, "turned-mesh-instance-load").instances.size(), 1u);
    const std::vector<glm::dvec3> quad = {{-0.5, h, -0.5}, {0.5, h, -0.5}, {0.5, h, 0.5}, {-0.5, h, 0.5}};
    test::expectTopDownMatches(
        doc, {{{"type", "direct"}, {"strategy", "light"}}, {{"type", "direct"}, {"strategy", "mis"}}},
        [&](glm::dvec3 x) { return kAlbedo / M_PI * test::polygonIrradiance(quad, x, Le); }, "turned-mesh-instance",
        kAlpha);
}

// Traced instances render as their copies: a sphere, a quad and a turned mesh placed twice
// each (traced through their group's tree), against the same scene with an id AOV layer
// (which makes every instance a copy), rendered with another seed. Both are unbiased
// estimates of the same pixels, each with the variance its `variance` layer estimates, so
// every pixel's difference is within z sqrt(var_a + var_b), z for a false failure rate of
// kAlpha over all pixels.
TEST(InstancesRender, TracedInstancesRenderAsTheirCopies) {
    const double Le = 8.0;
    json doc = test::diffusePlaneScene(256, 21, 0.0, 2.0, kAlbedo);
    doc["film"]["aovs"] = {"variance"};
    doc["shapes"].push_back({{"type", "quad"},
                             {"origin", {-1, 4, -1}},
                             {"edge_u", {2, 0, 0}},
                             {"edge_v", {0, 0, 2}},
                             {"emission", Le},
                             {"material", "black"}});
    json mesh = {{"type", "mesh"},
                 {"positions", {0, 0, 0, 0.6, 0, 0, 0, 0.6, 0, 0, 0, 0.6}},
                 {"indices", {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}},
                 {"to_world", {{"rotate", {{"axis", {1, 1, 0}}, {"angle", 30}}}}}};
    doc["shapes"].push_back(
        group("things",
              {{{"type", "sphere"}, {"center", {0.5, 0.4, 0}}, {"radius", 0.3}},
               {{"type", "quad"}, {"origin", {-0.8, 0.2, -0.8}}, {"edge_u", {0.5, 0.1, 0}}, {"edge_v", {0, 0.2, 0.6}}},
               mesh}));
    doc["shapes"].push_back(instance("things", {{"translate", {-0.7, 0, 0.6}}}));
    doc["shapes"].push_back(instance(
        "things", {{"scale", 0.8}, {"rotate", {{"axis", {0, 1, 0}}, {"angle", 70}}}, {"translate", {0.6, 0.1, -0.5}}}));
    const Scene traced = test::sceneFromJson(doc, "traced-things");
    ASSERT_EQ(traced.instances.size(), 2u);
    json copies = doc;
    copies["film"]["aovs"] = {"variance", "shape_id"};
    copies["sampler"]["seed"] = 22;
    const Scene copied = test::sceneFromJson(copies, "copied-things");
    ASSERT_TRUE(copied.instances.empty());
    const Image a = test::renderScene(traced), b = test::renderScene(copied);
    auto variance = [](const Image& image) -> const std::vector<float>& {
        for (const AovLayer& layer : image.aovs)
            if (layer.name == "variance") return layer.floats;
        throw std::logic_error("no variance layer");
    };
    const std::vector<float>&va = variance(a), &vb = variance(b);
    const size_t pixels = size_t(a.width) * a.height;
    const double z = test::zScore(kAlpha, int(pixels));
    int failures = 0;
    for (size_t p = 0; p < pixels; ++p) {
        const double d = double(a.rgb[3 * p]) - b.rgb[3 * p], v = double(va[3 * p]) + vb[3 * p];
        if (std::abs(d) > z * std::sqrt(v)) ++failures;
    }
    EXPECT_EQ(failures, 0);
    double sum = 0;
    for (float v : b.rgb) sum += v;
    EXPECT_GT(sum, 0.0);
}

// Shadow rays meet instances. A lamp left of the patch in view (x = -3, facing +x) lights
// it unless a traced instance is in the way, each out of the camera's view: a sphere (group
// radius 1, scaled by 1.5) around the lamp, or a wall at x = 0 (the unit quad turned
// upright by a matrix that also mirrors). Blocked, every pixel is 0 under the light, BRDF
// and MIS strategies; moved aside, the plane is lit.
TEST(InstancesRender, ShadowRaysAreBlockedByInstances) {
    const double Le = 5.0;
    json base = test::diffusePlaneScene(16, 17, 3.0, 1.5, kAlbedo);
    base["shapes"].push_back({{"type", "quad"},
                              {"origin", {-3, 2.5, -0.5}},
                              {"edge_u", {0, 1, 0}},
                              {"edge_v", {0, 0, 1}},
                              {"emission", Le},
                              {"material", "black"}});
    base["shapes"].push_back(group("ball", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}}}));
    base["shapes"].push_back(group("board", {kUnitQuad}));
    auto wall = [](double x) {
        return json{{0, 1, 0, x}, {10, 0, 0, 0.01}, {0, 0, 20, -10}, {0, 0, 0, 1}};  // (u, -, v) -> (x, 10 u, 20 v)
    };
    for (const std::string blocker : {"ball", "board"}) {
        const bool ball = blocker == "ball";
        for (const char* strategy : {"light", "bsdf", "mis"}) {
            json doc = base;
            doc["integrator"] = {{"type", "direct"}, {"strategy", strategy}};
            doc["shapes"].push_back(ball ? instance("ball", {{"scale", 1.5}, {"translate", {-3, 3, 0}}})
                                         : instance("board", wall(0)));
            const std::string name = "shadow-" + blocker + "-" + strategy;
            const Scene scene = test::sceneFromJson(doc, name);
            ASSERT_EQ(scene.instances.size(), 1u);
            const Image dark = test::renderScene(scene);
            for (float v : dark.rgb) ASSERT_EQ(v, 0.0f) << name;
        }
        json doc = base;
        doc["shapes"].push_back(ball ? instance("ball", {{"scale", 1.5}, {"translate", {-3, 3, 40}}})
                                     : instance("board", wall(-40)));
        const Image lit = test::renderJson(doc, "shadow-" + blocker + "-aside");
        double sum = 0;
        for (float v : lit.rgb) sum += v;
        EXPECT_GT(sum, 0.0) << blocker;
    }
}

// GPU memory grows with the instances' count, not their triangles: 1000 instances of a
// 19602-triangle mesh hold the mesh once (its primitives, normals and at most one wide
// node per primitive) and per instance a record, a primitive and at most one top-level
// node; a copy of the triangles would take a thousand times the mesh.
TEST(InstancesMemory, SceneArraysGrowWithInstancesNotTriangles) {
    const int n = 100, instances = 1000;
    json positions = json::array(), normals = json::array(), indices = json::array();
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            positions.insert(positions.end(), {i * 0.01, 0.0, j * 0.01});
            normals.insert(normals.end(), {0, 1, 0});
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            int a = j * n + i;
            indices.insert(indices.end(), {a, a + n, a + 1, a + 1, a + n, a + n + 1});
        }
    const size_t triangles = indices.size() / 3;
    json shapes = {
        group("tile", {{{"type", "mesh"}, {"positions", positions}, {"indices", indices}, {"normals", normals}}})};
    for (int k = 0; k < instances; ++k) {
        const int row = k / 40, column = k % 40;  // a grid of rows of 40
        shapes.push_back(instance("tile", {{"translate", {column * 1.5, 0, row * 1.5}}}));
    }
    const Scene scene = loadDoc(withShapes(shapes));
    ASSERT_EQ(scene.instances.size(), size_t(instances));
    const SceneArrays arrays = buildSceneArrays(scene);
    const size_t perTriangle = sizeof(gpu::Primitive) + sizeof(gpu::TriangleNormals) + sizeof(gpu::WideNode);
    const size_t perInstance = sizeof(gpu::Instance) + sizeof(gpu::Primitive) + sizeof(gpu::WideNode);
    const size_t slack = sizeof(gpu::WideNode);  // an empty scene's root
    EXPECT_LE(geometryBytes(arrays), triangles * perTriangle + instances * perInstance + slack);
    EXPECT_LT(geometryBytes(arrays) * 100, triangles * instances * sizeof(gpu::Primitive));
}
