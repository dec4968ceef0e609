// glTF import: the tests write small .gltf/.glb files (buffers as base64 data URIs, or a GLB
// binary chunk) and check transforms, cameras, lights and their units, emission, the
// unlit-model fallback, and that malformed files give one-line InputErrors, never crashes.
#include <cmath>
#include <cstring>
#include <numbers>

#include <gtest/gtest.h>

#include "gltf_builder.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;
using test::freshTempDir;
using test::GltfBuilder;
using test::loadError;
using test::writeFile;

namespace {

void expectVec(glm::vec3 actual, glm::vec3 expected, float tolerance = 1e-5f) {
    EXPECT_NEAR(actual.x, expected.x, tolerance);
    EXPECT_NEAR(actual.y, expected.y, tolerance);
    EXPECT_NEAR(actual.z, expected.z, tolerance);
}

std::string noteStartingWith(const Scene& s, const std::string& prefix) {
    for (const std::string& n : s.notes)
        if (n.rfind(prefix, 0) == 0) return n;
    return "";
}

}  // namespace

TEST(GltfLoad, NodeTranslationAndScaleAreApplied) {
    GltfBuilder b;
    b.addMeshNode(b.triangle(), {{"translation", {1, 2, 3}}, {"scale", {2, 2, 2}}});
    auto file = writeFile(freshTempDir() / "model.gltf", b.gltf());
    Scene s = loadScene(file);
    EXPECT_EQ(s.name, "model");
    ASSERT_EQ(s.shapes.size(), 1u);
    const Shape& mesh = s.shapes[0];
    EXPECT_EQ(mesh.type, ShapeType::Mesh);
    EXPECT_EQ(mesh.material, 0u);  // no glTF material: the default diffuse 0.8
    ASSERT_EQ(mesh.positions.size(), 3u);
    expectVec(mesh.positions[0], {1, 2, 3});
    expectVec(mesh.positions[1], {3, 2, 3});
    expectVec(mesh.positions[2], {1, 4, 3});
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(s.integrator.type, IntegratorType::Direct);
    EXPECT_EQ(s.integrator.strategy, Strategy::Mis);
    EXPECT_EQ(s.film.width, 512u);
}

TEST(GltfLoad, RotationTransformsNormalsAndParentsCompose) {
    GltfBuilder b;
    json prim = b.triangle();
    prim["attributes"]["NORMAL"] = b.positions({0, 0, 1, 0, 0, 1, 0, 0, 1});
    // Child rotated 90 degrees about +Y (quaternion x,y,z,w = 0, sin 45, 0, cos 45): +x -> -z,
    // +z -> +x; the parent then translates by (0, 0, 5).
    double h = std::sqrt(0.5);
    b.doc["meshes"].push_back({{"primitives", {prim}}});
    b.addNode({{"translation", {0, 0, 5}}, {"children", {1}}});
    b.addNode({{"rotation", {0, h, 0, h}}, {"mesh", 0}}, false);
    Scene s = loadScene(writeFile(freshTempDir() / "rotated.gltf", b.gltf()));
    ASSERT_EQ(s.shapes.size(), 1u);
    expectVec(s.shapes[0].positions[1], {0, 0, 4});
    expectVec(s.shapes[0].positions[2], {0, 1, 5});
    ASSERT_EQ(s.shapes[0].normals.size(), 3u);
    expectVec(s.shapes[0].normals[0], {1, 0, 0});
}

TEST(GltfLoad, MirroringTransformKeepsFrontFace) {
    GltfBuilder b;
    b.addMeshNode(b.triangle(), {{"scale", {-1, 1, 1}}});
    Scene s = loadScene(writeFile(freshTempDir() / "mirror.gltf", b.gltf()));
    ASSERT_EQ(s.shapes.size(), 1u);
    const Shape& m = s.shapes[0];
    glm::vec3 n = glm::cross(m.positions[m.indices[1]] - m.positions[m.indices[0]], m.positions[m.indices[2]] - m.positions[m.indices[0]]);
    EXPECT_GT(n.z, 0.0f);  // still counter-clockwise seen from +z
}

TEST(GltfLoad, StridedVerticesSmallIndicesAndStrips) {
    GltfBuilder b;
    // Interleaved position + normal (stride 24 bytes), a 4-vertex strip with byte indices.
    std::vector<float> interleaved = {0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1, 1, 1, 0, 0, 0, 1};
    int pos = b.addAccessor(interleaved.data(), interleaved.size() * 4, 5126, 4, "VEC3", 24);
    b.doc["accessors"].push_back({{"bufferView", pos}, {"byteOffset", 12}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}});
    std::vector<uint8_t> strip = {0, 1, 2, 3};
    int idx = b.addAccessor(strip.data(), strip.size(), 5121, 4, "SCALAR");
    b.addMeshNode({{"attributes", {{"POSITION", pos}, {"NORMAL", 1}}}, {"indices", idx}, {"mode", 5}});
    Scene s = loadScene(writeFile(freshTempDir() / "strip.gltf", b.gltf()));
    ASSERT_EQ(s.shapes.size(), 1u);
    const Shape& m = s.shapes[0];
    expectVec(m.positions[3], {1, 1, 0});
    expectVec(m.normals[3], {0, 0, 1});
    ASSERT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 2, 1, 3}));  // second strip triangle re-wound
}

TEST(GltfLoad, CameraFromNodeAndFovOverride) {
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}, {"aspectRatio", 2.0}}}}};
    b.addNode({{"camera", 0}, {"translation", {0, 1, 10}}});
    auto file = writeFile(freshTempDir() / "cam.gltf", b.gltf());
    Scene s = loadScene(file);
    expectVec(s.camera.eye, {0, 1, 10});
    expectVec(s.camera.target, {0, 1, 9});  // looks down -Z
    expectVec(s.camera.up, {0, 1, 0});
    EXPECT_NEAR(s.camera.fovY, 0.5 * 180.0 / std::numbers::pi, 1e-4);
    EXPECT_EQ(s.film.width, 512u);  // the camera's aspect ratio yields to the film

    Scene t = loadScene(file, {parseOverride("camera.fov_y=30"), parseOverride("film.width=64")});
    EXPECT_FLOAT_EQ(t.camera.fovY, 30.0f);
    expectVec(t.camera.eye, {0, 1, 10});
    EXPECT_EQ(t.film.width, 64u);
}

TEST(GltfLoad, FramingCameraWithoutGltfCamera) {
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    Scene s = loadScene(writeFile(freshTempDir() / "frame.gltf", b.gltf()));
    // Bounds [0,1]x[0,1]x[0]: centre (0.5, 0.5, 0), bounding radius sqrt(2)/2; square film and
    // fov 40 degrees put the eye sqrt(2)/2 / sin(20 deg) = 2.0674 away, in the three-quarter
    // direction (cos 30 sin 45, sin 30, cos 30 cos 45): 45 degrees round from +z, 30 above.
    expectVec(s.camera.target, {0.5f, 0.5f, 0.0f});
    expectVec(s.camera.eye, {1.76604f, 1.53372f, 1.26604f}, 1e-3f);
    EXPECT_FLOAT_EQ(s.camera.fovY, 40.0f);
}

TEST(GltfLoad, PunctualLightsInPenumbraUnits) {
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensionsRequired"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"color", {1, 0.5, 0}}, {"intensity", 5}},
        {{"type", "directional"}, {"intensity", 2}}};
    b.addNode({{"translation", {0, 3, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    // Rotation of -90 degrees about +X turns the light's -Z into -Y (straight down).
    double h = std::sqrt(0.5);
    b.addNode({{"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    Scene s = loadScene(writeFile(freshTempDir() / "lights.gltf", b.gltf()));
    ASSERT_EQ(s.lights.size(), 2u);  // and no environment fallback
    EXPECT_EQ(s.lights[0].type, LightType::Point);
    expectVec(s.lights[0].position, {0, 3, 0});
    expectVec(s.lights[0].intensity, {5, 2.5, 0});  // candela = W/sr, times colour
    EXPECT_EQ(s.lights[1].type, LightType::Directional);
    expectVec(s.lights[1].direction, {0, -1, 0});
    expectVec(s.lights[1].intensity, {2, 2, 2});  // lux = W/m^2
    EXPECT_TRUE(s.notes.empty());
}

TEST(GltfLoad, EmissiveStrengthAndBaseColour) {
    GltfBuilder b;
    json prim = b.triangle();
    prim["material"] = 0;
    b.addMeshNode(prim);
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1.5, 0.5, 0.25, 1}}}},
                           {"emissiveFactor", {1, 0.5, 0.25}},
                           {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}}};
    Scene s = loadScene(writeFile(freshTempDir() / "glow.gltf", b.gltf()));
    ASSERT_EQ(s.shapes.size(), 1u);
    expectVec(s.shapes[0].emission, {4, 2, 1});
    ASSERT_EQ(s.materials.size(), 2u);
    EXPECT_EQ(s.shapes[0].material, 1u);
    // SCENE_FORMAT.md v2: a glTF material is `pbr`, with glTF's defaults metallic 1 and
    // roughness 1 where the file gives no factors.
    EXPECT_EQ(s.materials[1].type, MaterialType::Pbr);
    expectVec(s.materials[1].pbr.baseColor, {1, 0.5, 0.25});  // clamped to [0, 1]
    EXPECT_EQ(s.materials[1].pbr.metallic, 1.0f);
    EXPECT_EQ(s.materials[1].pbr.roughness, 1.0f);
    EXPECT_EQ(s.lights.size(), 2u);  // emissive materials do not take the studio lights' place
    // A negative strength is reported at its own path, not as the emissiveFactor it scales.
    b.doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = -2;
    try {
        loadScene(writeFile(freshTempDir() / "negative.gltf", b.gltf()));
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(
                      "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength: negative"),
                  std::string::npos)
            << e.what();
    }
}

TEST(GltfLoad, MetallicRoughnessFactorsBecomePbr) {
    GltfBuilder b;
    json prim = b.triangle();
    prim["material"] = 0;
    b.addMeshNode(prim);
    b.doc["materials"] = {
        {{"pbrMetallicRoughness",
          {{"baseColorFactor", {0.2, 0.4, 0.6, 0.5}}, {"metallicFactor", 0.25}, {"roughnessFactor", 0.75}}}}};
    Scene s = loadScene(writeFile(freshTempDir() / "factors.gltf", b.gltf()));
    ASSERT_EQ(s.materials.size(), 2u);
    EXPECT_EQ(s.materials[1].type, MaterialType::Pbr);
    expectVec(s.materials[1].pbr.baseColor, {0.2f, 0.4f, 0.6f});
    EXPECT_EQ(s.materials[1].pbr.metallic, 0.25f);
    EXPECT_EQ(s.materials[1].pbr.roughness, 0.75f);

    // Out of [0, 1]: one line naming the file and the glTF JSON path.
    for (const char* key : {"metallicFactor", "roughnessFactor"})
        for (double bad : {-0.5, 1.5}) {
            GltfBuilder c;
            json p = c.triangle();
            p["material"] = 0;
            c.addMeshNode(p);
            c.doc["materials"] = {{{"pbrMetallicRoughness", {{key, bad}}}}};
            std::string err = loadError(writeFile(freshTempDir() / "bad-factor.gltf", c.gltf()));
            EXPECT_NE(err.find("bad-factor.gltf"), std::string::npos) << err;
            EXPECT_NE(err.find(std::string("materials[0].pbrMetallicRoughness.") + key), std::string::npos) << err;
            EXPECT_NE(err.find("[0, 1]"), std::string::npos) << err;
        }
}

// A model without lights gets a sky and a key light from the camera's upper left (45 degrees
// to its left and 45 above its view axis, so 60 degrees from the view axis), said in a note.
TEST(GltfLoad, UnlitModelGetsStudioLightsAndNote) {
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    auto file = writeFile(freshTempDir() / "plain.glb", b.glb());
    Scene s = loadScene(file);
    ASSERT_EQ(s.lights.size(), 2u);
    EXPECT_EQ(s.lights[0].type, LightType::Environment);
    expectVec(s.lights[0].intensity, {0.4f, 0.4f, 0.4f});
    EXPECT_EQ(s.lights[1].type, LightType::Directional);
    expectVec(s.lights[1].intensity, {2, 2, 2});
    const Camera& c = s.camera;
    glm::vec3 view = glm::normalize(c.target - c.eye);
    glm::vec3 right = glm::normalize(glm::cross(view, c.up));
    glm::vec3 up = glm::cross(right, view);
    glm::vec3 toKey = -s.lights[1].direction;
    EXPECT_NEAR(glm::length(toKey), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(toKey, -view), 0.5f, 1e-6f);          // 60 degrees from the view axis
    EXPECT_NEAR(glm::dot(toKey, up), std::sqrt(0.5f), 1e-6f);  // 45 degrees above it
    EXPECT_NEAR(glm::dot(toKey, right), -0.5f, 1e-6f);         // on the camera's left
    EXPECT_EQ(s.notes, (std::vector<std::string>{file.string() +
                                                 ": no lights in the model; lit by a sky (radiance 0.4) and a key "
                                                 "light (irradiance 2) from the camera's upper left (--set lights=[] "
                                                 "for none)"}));
    // The binary container carried the same triangle.
    ASSERT_EQ(s.shapes.size(), 1u);
    expectVec(s.shapes[0].positions[2], {0, 1, 0});
}

// Emissive materials are not lights in a model viewer's sense: ClearCoatTest's emissive
// labels left the rest of the model unlit (almost black). Its own lights or --set lights
// replace the studio lights; `--set lights=[]` keeps the model's emission alone.
TEST(GltfLoad, StudioLightsUnlessTheModelOrCommandLineBringsLights) {
    GltfBuilder emissive;
    json p = emissive.triangle();
    p["material"] = 0;
    emissive.addMeshNode(p);
    emissive.doc["materials"] = {{{"emissiveFactor", {1, 1, 1}}}};
    auto file = writeFile(freshTempDir() / "emissive.gltf", emissive.gltf());
    EXPECT_EQ(loadScene(file).lights.size(), 2u);

    Scene none = loadScene(file, {{"lights", "[]"}});
    EXPECT_TRUE(none.lights.empty());
    EXPECT_TRUE(none.notes.empty()) << none.notes[0];  // the emitter lights it: no "black" note

    Scene given = loadScene(file, {{"lights", R"([{"type": "point", "position": [0, 0, 1], "power": 1}])"}});
    ASSERT_EQ(given.lights.size(), 1u);
    EXPECT_EQ(given.lights[0].type, LightType::Point);

    GltfBuilder lit;
    lit.addMeshNode(lit.triangle());
    lit.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 1}}};
    lit.addNode({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    Scene own = loadScene(writeFile(freshTempDir() / "lit.gltf", lit.gltf()));
    ASSERT_EQ(own.lights.size(), 1u);
    EXPECT_EQ(own.lights[0].type, LightType::Point);

    // No light and no emitter, asked for: the scene's usual warning.
    GltfBuilder plain;
    plain.addMeshNode(plain.triangle());
    auto plainFile = writeFile(freshTempDir() / "plain.gltf", plain.gltf());
    Scene dark = loadScene(plainFile, {{"lights", "[]"}});
    EXPECT_EQ(dark.notes, (std::vector<std::string>{plainFile.string() +
                                                    ": no lights and no emitting shapes; the image will be black"}));
}

TEST(GltfLoad, DegenerateTrianglesSkippedWithNote) {
    GltfBuilder b;
    b.addMeshNode({{"attributes", {{"POSITION", b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0})}}},
                   {"indices", b.indices({0, 1, 2, 0, 1, 3, 1, 1, 2})}});
    auto file = writeFile(freshTempDir() / "degenerate.gltf", b.gltf());
    Scene s = loadScene(file);
    ASSERT_EQ(s.shapes.size(), 1u);
    EXPECT_EQ(s.shapes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(noteStartingWith(s, file.string() + ": skipped 2 degenerate"), file.string() + ": skipped 2 degenerate (zero-area) triangles");
}

TEST(GltfLoad, GltfShapeInJsonScene) {
    auto dir = freshTempDir();
    std::filesystem::create_directories(dir / "models");
    GltfBuilder b;
    json prim = b.triangle();
    prim["material"] = 0;
    b.addMeshNode(prim);
    b.doc["materials"] = {{{"emissiveFactor", {1, 1, 1}}}};
    b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    b.addNode({{"camera", 0}, {"translation", {0, 0, 50}}});
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 1}}};
    b.addNode({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    writeFile(dir / "models" / "tri.gltf", b.gltf());
    // Power 2 pi over the triangle's area 0.5: Le = P/(pi A) = 4.
    auto file = writeFile(dir / "scene.json", R"({
      "materials": {"red": {"albedo": [0.9, 0.1, 0.1]}},
      "shapes": [{"type": "gltf", "file": "models/tri.gltf", "material": "red", "power": 6.283185307179586}],
      "lights": [{"type": "environment", "radiance": 0.5}]})");
    Scene s = loadScene(file);
    ASSERT_EQ(s.shapes.size(), 1u);
    EXPECT_EQ(s.shapes[0].material, 1u);
    EXPECT_EQ(s.materials.size(), 2u);  // the file's material was replaced, not added
    expectVec(s.shapes[0].emission, {4, 4, 4});
    ASSERT_EQ(s.lights.size(), 2u);  // the file's point light, then the scene's environment
    EXPECT_EQ(s.lights[0].type, LightType::Point);
    expectVec(s.camera.eye, {0, 1, 5});  // the file's camera is ignored
}

TEST(GltfLoad, IndexOutOfRangeMessage) {
    GltfBuilder b;
    b.addMeshNode({{"attributes", {{"POSITION", b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}, {"indices", b.indices({0, 1, 99})}});
    auto file = writeFile(freshTempDir() / "model.gltf", b.gltf());
    EXPECT_EQ(loadError(file), file.string() + ": meshes[0].primitives[0].indices: index 99 out of range (3 vertices)");
}

TEST(GltfLoad, AccessorPastBufferView) {
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    b.doc["accessors"][0]["count"] = 4;  // 48 bytes from a 36-byte view
    auto file = writeFile(freshTempDir() / "short.gltf", b.gltf());
    EXPECT_EQ(loadError(file), file.string() + ": accessors[0]: reads past the end of bufferView 0");
    b.doc["accessors"][0]["count"] = 3;
    b.doc["bufferViews"][0]["byteStride"] = 8;  // smaller than a VEC3 of floats
    EXPECT_NE(loadError(writeFile(file, b.gltf())).find("bufferViews[0].byteStride"), std::string::npos);
}

TEST(GltfLoad, NodeCyclesAreErrors) {
    GltfBuilder b;
    b.addMeshNode(b.triangle(), {{"children", {1}}});
    b.addNode({{"children", {0}}}, false);
    auto file = writeFile(freshTempDir() / "cycle.gltf", b.gltf());
    std::string message = loadError(file);
    EXPECT_EQ(message.rfind(file.string() + ": nodes[", 0), 0u) << message;
    EXPECT_NE(message.find("node cycle"), std::string::npos) << message;

    GltfBuilder self;
    self.addMeshNode(self.triangle(), {{"children", {0}}});
    EXPECT_NE(loadError(writeFile(file, self.gltf())).find("node cycle: node 0 is its own child"), std::string::npos);

    GltfBuilder twice;  // a scene listing the same root twice
    int n = twice.addMeshNode(twice.triangle());
    twice.doc["scenes"][0]["nodes"].push_back(n);
    EXPECT_NE(loadError(writeFile(file, twice.gltf())).find("reached twice"), std::string::npos);
}

TEST(GltfLoad, UnsupportedRequiredExtension) {
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    b.doc["extensionsUsed"] = {"EXT_meshopt_compression"};
    b.doc["extensionsRequired"] = {"EXT_meshopt_compression"};
    auto file = writeFile(freshTempDir() / "ext.gltf", b.gltf());
    EXPECT_EQ(loadError(file),
              file.string() +
                  ": extensionsRequired[0]: unsupported required extension \"EXT_meshopt_compression\" "
                  "(Penumbra reads KHR_lights_punctual, KHR_materials_emissive_strength and "
                  "KHR_texture_transform)");
}

// A Draco-compressed mesh's accessors have no bufferView: the file must be refused for the
// extension it requires, not for the accessor that tinygltf cannot read without it.
TEST(GltfLoad, CompressedMeshNamesItsRequiredExtension) {
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    b.doc["accessors"][0].erase("bufferView");
    b.doc["extensionsUsed"] = {"KHR_lights_punctual", "KHR_draco_mesh_compression"};
    b.doc["extensionsRequired"] = {"KHR_lights_punctual", "KHR_draco_mesh_compression"};
    auto file = writeFile(freshTempDir() / "draco.gltf", b.gltf());
    std::string message = loadError(file);
    EXPECT_EQ(message.rfind(file.string() + ": extensionsRequired[1]: unsupported required extension "
                                            "\"KHR_draco_mesh_compression\"",
                            0),
              0u)
        << message;
}

// Extensions a file only uses are ignored with one note naming them (each once, capped).
TEST(GltfLoad, IgnoredOptionalExtensionsGetOneNote) {
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    b.doc["extensionsUsed"] = {"KHR_materials_clearcoat", "KHR_lights_punctual", "KHR_materials_transmission",
                               "KHR_materials_clearcoat", std::string(500, 'X')};
    auto file = writeFile(freshTempDir() / "optional.gltf", b.gltf());
    Scene s = loadScene(file);
    EXPECT_EQ(noteStartingWith(s, file.string() + ": ignoring"),
              file.string() + ": ignoring optional extensions KHR_materials_clearcoat, KHR_materials_transmission, " +
                  std::string(61, 'X') + "... (the model renders without them)");

    GltfBuilder plain;  // supported ones only: no note
    plain.addMeshNode(plain.triangle());
    plain.doc["extensionsUsed"] = {"KHR_lights_punctual", "KHR_texture_transform"};
    EXPECT_EQ(noteStartingWith(loadScene(writeFile(file, plain.gltf())), file.string() + ": ignoring"), "");
}

TEST(GltfLoad, MalformedFilesAreInputErrors) {
    auto dir = freshTempDir();
    std::string garbage;
    for (int i = 0; i < 4096; ++i) garbage += char((i * 2654435761u) >> 13);
    for (const char* name : {"garbage.glb", "garbage.gltf"}) {
        auto file = writeFile(dir / name, garbage);
        EXPECT_EQ(loadError(file).rfind(file.string() + ": ", 0), 0u);
    }
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    std::string text = b.gltf();
    auto truncated = writeFile(dir / "truncated.gltf", text.substr(0, text.size() / 2));
    EXPECT_EQ(loadError(truncated).rfind(truncated.string() + ": ", 0), 0u);
    // A GLB whose header claims more JSON than there is.
    std::string glb = b.glb();
    uint32_t huge = 0x7fffffff;
    std::memcpy(glb.data() + 12, &huge, 4);
    auto badGlb = writeFile(dir / "bad.glb", glb);
    EXPECT_EQ(loadError(badGlb).rfind(badGlb.string() + ": ", 0), 0u);
    // A GLB cut short inside its binary chunk.
    auto cut = writeFile(dir / "cut.glb", b.glb().substr(0, b.glb().size() - 8));
    EXPECT_EQ(loadError(cut).rfind(cut.string() + ": ", 0), 0u);
    // A bufferView reaching past its buffer, a mesh index that does not exist, a missing file.
    GltfBuilder v;
    v.addMeshNode(v.triangle());
    v.doc["bufferViews"][0]["byteLength"] = 4000;
    EXPECT_EQ(loadError(writeFile(dir / "view.gltf", v.gltf())).rfind((dir / "view.gltf").string() + ": ", 0), 0u);
    GltfBuilder m;
    m.addMeshNode(m.triangle());
    m.addNode({{"mesh", 3}});
    EXPECT_NE(loadError(writeFile(dir / "mesh.gltf", m.gltf())).find("nodes[1].mesh: mesh 3 does not exist"), std::string::npos);
    GltfBuilder z;  // an accessor without bufferView (all zeros) claiming 10^12 elements
    z.addMeshNode({{"attributes", {{"POSITION", 0}}}});
    z.doc["accessors"] = {{{"componentType", 5126}, {"count", 1000000000000}, {"type", "VEC3"}}};
    z.bin = {0, 0, 0, 0};
    EXPECT_NE(loadError(writeFile(dir / "zeros.gltf", z.gltf())).find("accessors[0].count: too large"), std::string::npos);
    EXPECT_EQ(loadError(dir / "absent.glb"), (dir / "absent.glb").string() + ": cannot open file (no such file)");
}
