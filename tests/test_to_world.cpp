// Per-shape transforms (SCENE_FORMAT.md "to_world", host/scene/transform.h): each shape's
// data after loading against the closed form of its transform — scale, then rotate, then
// translate; normals by the inverse transpose; a mirror keeps the front face; emission
// from power over the moved area; glTF models move with their lights — and every bad
// transform refused with its JSON path.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "scene/load.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

fs::path freshDir(const std::string& name) { return test::freshOutputDir("to-world", name); }

json sceneWith(const json& shape) {
    return {{"shapes", {shape}}, {"lights", {{{"type", "point"}, {"position", {0, 5, 0}}, {"power", 10}}}}};
}

Scene loadIn(const fs::path& dir, const json& doc) {
    std::ofstream(dir / "scene.json") << doc.dump();
    return loadScene(dir / "scene.json");
}

void expectNear(glm::vec3 got, glm::vec3 want, const char* what) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-5f) << what << "[" << c << "]";
}

// The geometric front normal of a mesh triangle: counter-clockwise = front (SCENE_FORMAT.md).
glm::vec3 frontOf(const Shape& s, size_t t) {
    const glm::vec3 a = s.positions[s.indices[3 * t]], b = s.positions[s.indices[3 * t + 1]],
                    c = s.positions[s.indices[3 * t + 2]];
    return glm::normalize(glm::cross(b - a, c - a));
}

std::set<std::tuple<float, float, float>> quadCorners(const Shape& q) {
    std::set<std::tuple<float, float, float>> corners;
    for (glm::vec3 p : {q.origin, q.origin + q.edgeU, q.origin + q.edgeV, q.origin + q.edgeU + q.edgeV})
        corners.insert({std::round(p.x * 1e4f) / 1e4f, std::round(p.y * 1e4f) / 1e4f, std::round(p.z * 1e4f) / 1e4f});
    return corners;
}

// loadScene of `doc` fails with a message containing `needle`.
void expectRefused(const fs::path& dir, const json& doc, const std::string& needle) {
    try {
        loadIn(dir, doc);
        ADD_FAILURE() << "accepted: " << doc.dump();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what() << " / " << needle;
    }
}

const json kTriangle = {{"type", "mesh"}, {"positions", {0, 0, 0, 1, 0, 0, 0, 1, 0}}, {"indices", {0, 1, 2}}};

}  // namespace

TEST(ToWorld, SphereIsScaledThenRotatedThenTranslated) {
    const fs::path dir = freshDir("sphere");
    json sphere = {{"type", "sphere"}, {"center", {1, 0, 0}}, {"radius", 0.5}, {"power", 100}};
    sphere["to_world"] = {{"scale", 2}, {"rotate", {{"axis", {0, 0, 3}}, {"angle", 90}}}, {"translate", {0, 0, 5}}};
    const Scene scene = loadIn(dir, sceneWith(sphere));
    const Shape& s = scene.shapes[0];
    // (1,0,0) scaled to (2,0,0), turned a quarter counter-clockwise about +z to (0,2,0), moved by +5 z.
    expectNear(s.center, {0, 2, 5}, "center");
    EXPECT_NEAR(s.radius, 1.0f, 1e-6f);
    // Le = P / (4 pi^2 r^2) with the moved radius 1.
    EXPECT_NEAR(s.emission.x, 100.0 / (4.0 * M_PI * M_PI), 1e-4);
    // The same map as a matrix: a uniform scale times a rotation is accepted.
    sphere["to_world"] = {{0, -2, 0, 0}, {2, 0, 0, 0}, {0, 0, 2, 5}, {0, 0, 0, 1}};
    const Shape& m = loadIn(dir, sceneWith(sphere)).shapes[0];
    expectNear(m.center, {0, 2, 5}, "matrix center");
    EXPECT_NEAR(m.radius, 1.0f, 1e-6f);
}

TEST(ToWorld, QuadMatrixAndPartsAgreeAndPowerUsesTheMovedArea) {
    const fs::path dir = freshDir("quad");
    json quad = {{"type", "quad"}, {"origin", {0, 0, 0}}, {"edge_u", {1, 0, 0}}, {"edge_v", {0, 1, 0}}};
    quad["power"] = 6 * M_PI;
    quad["to_world"] = {{2, 0, 0, 1}, {0, 3, 0, 2}, {0, 0, 1, 3}, {0, 0, 0, 1}};
    const Shape q = loadIn(dir, sceneWith(quad)).shapes[0];
    expectNear(q.origin, {1, 2, 3}, "origin");
    expectNear(q.edgeU, {2, 0, 0}, "edge_u");
    expectNear(q.edgeV, {0, 3, 0}, "edge_v");
    // Area 2 x 3 = 6 after the map, so Le = P / (pi A) = 1.
    EXPECT_NEAR(q.emission.x, 1.0f, 1e-5f);
    quad["to_world"] = {{"scale", {2, 3, 1}}, {"translate", {1, 2, 3}}};
    const Shape p = loadIn(dir, sceneWith(quad)).shapes[0];
    expectNear(p.origin, q.origin, "parts origin");
    expectNear(p.edgeU, q.edgeU, "parts edge_u");
    expectNear(p.edgeV, q.edgeV, "parts edge_v");
}

TEST(ToWorld, MeshNormalsTransformByTheInverseTranspose) {
    const fs::path dir = freshDir("mesh");
    // A triangle in the plane x + y = 0 with the plane's normal at every vertex.
    json mesh = {{"type", "mesh"},
                 {"positions", {0, 0, 0, 0, 0, 1, 1, -1, 0}},
                 {"indices", {0, 1, 2}},
                 {"normals", {1, 1, 0, 1, 1, 0, 1, 1, 0}},
                 {"power", M_PI}};
    mesh["to_world"] = {{"scale", {2, 1, 1}}};
    const Shape s = loadIn(dir, sceneWith(mesh)).shapes[0];
    expectNear(s.positions[2], {2, -1, 0}, "moved vertex");
    // (1,1,0) through diag(2,1,1)^-T = diag(1/2,1,1): (1/2, 1, 0), normalized (1, 2, 0)/sqrt(5),
    // still perpendicular to the moved edges (2,-1,0) and (0,0,1).
    for (glm::vec3 n : s.normals) expectNear(n, glm::vec3(1, 2, 0) / std::sqrt(5.0f), "normal");
    // The moved triangle's area is |(0,0,1) x (2,-1,0)| / 2 = sqrt(5)/2: Le = P / (pi A).
    EXPECT_NEAR(s.emission.x, 2.0 / std::sqrt(5.0), 1e-5);
}

TEST(ToWorld, AMirrorKeepsTheFrontFace) {
    const fs::path dir = freshDir("mirror");
    // Mirroring x leaves the +z front of a triangle and a quad in the xy plane at +z.
    json mesh = kTriangle;
    mesh["to_world"] = {{"scale", {-1, 1, 1}}};
    const Shape m = loadIn(dir, sceneWith(mesh)).shapes[0];
    expectNear(frontOf(m, 0), {0, 0, 1}, "mesh front");
    std::set<std::tuple<float, float, float>> moved;
    for (glm::vec3 p : m.positions) moved.insert({p.x, p.y, p.z});
    EXPECT_EQ(moved, (std::set<std::tuple<float, float, float>>{{0, 0, 0}, {-1, 0, 0}, {0, 1, 0}}));

    json quad = {{"type", "quad"}, {"origin", {0, 0, 0}}, {"edge_u", {1, 0, 0}}, {"edge_v", {0, 2, 0}}};
    quad["to_world"] = {{-1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    const Shape q = loadIn(dir, sceneWith(quad)).shapes[0];
    expectNear(glm::normalize(glm::cross(q.edgeU, q.edgeV)), {0, 0, 1}, "quad front");
    EXPECT_EQ(quadCorners(q),
              (std::set<std::tuple<float, float, float>>{{0, 0, 0}, {-1, 0, 0}, {0, 2, 0}, {-1, 2, 0}}));
    // Without a mirror the winding stays as given.
    mesh["to_world"] = {{"rotate", {{"axis", {1, 0, 0}}, {"angle", 180}}}};
    expectNear(frontOf(loadIn(dir, sceneWith(mesh)).shapes[0], 0), {0, 0, -1}, "turned mesh front");
}

TEST(ToWorld, GltfModelsMoveWithTheirLightsAndMeshFilesMoveToo) {
    const fs::path dir = freshDir("gltf");
    const fs::path model = fs::path(PENUMBRA_SOURCE_DIR) / "scenes" / "models" / "torus_knot.gltf";
    fs::copy_file(model, dir / "knot.gltf", fs::copy_options::overwrite_existing);
    json shape = {{"type", "gltf"}, {"file", "knot.gltf"}};
    const Scene plain = loadIn(dir, sceneWith(shape));
    shape["to_world"] = {{"scale", 2}, {"translate", {1, 2, 3}}};
    const Scene moved = loadIn(dir, sceneWith(shape));
    ASSERT_EQ(plain.shapes.size(), moved.shapes.size());
    ASSERT_FALSE(plain.shapes[0].positions.empty());
    for (size_t i = 0; i < plain.shapes[0].positions.size(); i += 97)
        expectNear(moved.shapes[0].positions[i], 2.0f * plain.shapes[0].positions[i] + glm::vec3(1, 2, 3), "vertex");

    // A spot light at (0, 3, 0) shining down -z (glTF's light axis), turned -90 degrees about
    // x and moved: position (0, 0, -3) + (1, 0, 0), axis -y.
    const json lamp = {
        {"asset", {{"version", "2.0"}}},
        {"extensionsUsed", {"KHR_lights_punctual"}},
        {"extensions",
         {{"KHR_lights_punctual", {{"lights", {{{"type", "spot"}, {"intensity", 5}, {"spot", json::object()}}}}}}}},
        {"nodes", {{{"translation", {0, 3, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}}},
        {"scenes", {{{"nodes", {0}}}}},
        {"scene", 0}};
    std::ofstream(dir / "lamp.gltf") << lamp.dump();
    json lampShape = {{"type", "gltf"}, {"file", "lamp.gltf"}};
    lampShape["to_world"] = {{"rotate", {{"axis", {1, 0, 0}}, {"angle", -90}}}, {"translate", {1, 0, 0}}};
    const Scene lit = loadIn(dir, sceneWith(lampShape));
    ASSERT_EQ(lit.lights.size(), 2u);  // the model's spot (shapes load first), the scene's point light
    EXPECT_EQ(lit.lights[0].type, LightType::Spot);
    expectNear(lit.lights[0].position, {1, 0, -3}, "spot position");
    expectNear(lit.lights[0].direction, {0, -1, 0}, "spot axis");

    std::ofstream(dir / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    json file = {{"type", "mesh"}, {"file", "tri.obj"}, {"to_world", {{"translate", {0, 0, 7}}}}};
    const Shape f = loadIn(dir, sceneWith(file)).shapes[0];
    expectNear(f.positions[1], {1, 0, 7}, "mesh file vertex");
}

TEST(ToWorld, BadTransformsAreRefusedWithTheJsonPath) {
    const fs::path dir = freshDir("bad");
    const json sphere = {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}};
    auto with = [](json shape, const json& toWorld) {
        shape["to_world"] = toWorld;
        return sceneWith(shape);
    };
    expectRefused(dir, with(sphere, {{"scale", {1, 2, 1}}}),
                  "shapes[0].to_world.scale: a sphere takes only a uniform scale");
    expectRefused(dir, with(sphere, {{1, 0.5, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}),
                  "shapes[0].to_world: a sphere takes only a uniform scale");
    expectRefused(dir, with(kTriangle, {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 1, 1}}),
                  "shapes[0].to_world[3]: the last row must be [0, 0, 0, 1]");
    expectRefused(dir, with(kTriangle, {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}),
                  "shapes[0].to_world: a to_world matrix has 4 rows of 4 numbers");
    expectRefused(dir, with(kTriangle, {{1, 0, 0, 0}, {0, 1, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}),
                  "shapes[0].to_world[1]: a to_world matrix has 4 rows of 4 numbers");
    expectRefused(dir, with(kTriangle, {{1, 0, 0, 0}, {2, 0, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}),
                  "shapes[0].to_world: not invertible");
    expectRefused(dir, with(kTriangle, {{"scale", {1, 0, 1}}}), "shapes[0].to_world.scale: a scale of 0");
    expectRefused(dir, with(kTriangle, {{"rotate", {{"axis", {0, 0, 0}}, {"angle", 30}}}}),
                  "shapes[0].to_world.rotate.axis: must be a non-zero vector");
    expectRefused(dir, with(kTriangle, {{"rotation", {}}}), "shapes[0].to_world");
    expectRefused(dir, with(kTriangle, "identity"), "shapes[0].to_world: expected a 4x4 matrix");
    expectRefused(dir, with(kTriangle, {{"translate", {0, 2e8, 0}}}), "shapes[0].to_world: moves the mesh outside");
    expectRefused(dir, with(sphere, {{"scale", 1e9}}), "shapes[0].to_world: moves the sphere outside");
}

TEST(ToWorld, ATexturedSphereMayBeMovedAndScaledButNotTurned) {
    const fs::path dir = freshDir("textured-sphere");
    writePng(dir / "checker.png", Image{2, 2, {1, 1, 1, 0, 0, 0, 0, 0, 0, 1, 1, 1}, {}});
    json doc = sceneWith({{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "checker"}});
    doc["materials"] = {{"checker", {{"type", "diffuse"}, {"albedo", {{"texture", "checker.png"}}}}}};
    doc["shapes"][0]["to_world"] = {{"scale", 2}, {"translate", {0, 1, 0}}};
    EXPECT_NO_THROW(loadIn(dir, doc));
    // Spheres carry no frame: a turned texture would render unturned, so it is refused.
    doc["shapes"][0]["to_world"] = {{"rotate", {{"axis", {0, 1, 0}}, {"angle", 30}}}};
    expectRefused(dir, doc, "shapes[0].to_world: rotates or mirrors a textured sphere");
    doc["shapes"][0]["to_world"] = {{"scale", -1}};
    expectRefused(dir, doc, "shapes[0].to_world: rotates or mirrors a textured sphere");
    // An untextured sphere looks the same turned: accepted.
    doc["shapes"][0].erase("material");
    doc["shapes"][0]["to_world"] = {{"rotate", {{"axis", {0, 1, 0}}, {"angle", 30}}}};
    EXPECT_NO_THROW(loadIn(dir, doc));
}
