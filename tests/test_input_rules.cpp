// The input rules every reader shares (docs/design/contract-decisions.md): nesting depth, duplicate keys, the size
// cap, errno's words for failures,
// number ranges, glTF versions and integer fields, glTF file access, no echo of file
// contents, and linear parsing (JSON paths turned into text only for a message).
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "batch/job_file.h"
#include "core/input_file.h"
#include "gltf_builder.h"
#include "gpu_fixture.h"
#include "render_helpers.h"
#include "scene/json_parse.h"
#include "scene/json_reader.h"
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

std::string nestedArrays(size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

// {"a": {"a": ... {} ...}} with `depth` objects.
std::string nestedObjects(size_t depth) {
    std::string text;
    for (size_t i = 1; i < depth; ++i) text += "{\"a\": ";
    text += "{}";
    return text + std::string(depth - 1, '}');
}

// The InputError message of loading a job file; fails the test when there is none.
std::string jobError(const fs::path& file) {
    try {
        loadJobFile(file);
    } catch (const InputError& e) {
        std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        return message;
    }
    ADD_FAILURE() << "expected InputError loading " << file;
    return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Restores "only inside the folder" at the end of a test that allows any path.
struct AllowAnyPath {
    AllowAnyPath() { setAllowAnyPath(true); }
    ~AllowAnyPath() { setAllowAnyPath(false); }
};

}  // namespace

// --- nesting depth ----------------------------------------------------------------------

TEST(InputRules, DepthScanCountsBracketsOutsideStringsOnly) {
    EXPECT_NO_THROW(checkJsonDepth(nestedArrays(kMaxJsonDepth), "f"));
    try {
        checkJsonDepth(nestedArrays(kMaxJsonDepth + 1), "f");
        ADD_FAILURE() << "257 levels accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "f: line 1, column 257: nested deeper than 256 levels");
    }
    // Brackets inside strings, escaped quotes included, are text.
    std::string inString = "[\"\\\"" + std::string(1000, '[') + "\"]";
    EXPECT_NO_THROW(checkJsonDepth(inString, "f"));
    EXPECT_NO_THROW(parseJsonText(inString, "f"));
}

TEST(InputRules, DeeplyNestedSceneAndSetValueAreRefused) {
    auto dir = freshTempDir();
    auto scene = writeFile(dir / "deep.json", "{\"film\": " + nestedArrays(100000) + "}");
    EXPECT_EQ(loadError(scene), scene.string() + ": line 1, column 265: nested deeper than 256 levels");
    auto plain = writeFile(dir / "plain.json", "{}");
    std::string message = loadError(plain, {Override{"camera.eye", nestedArrays(100000)}});
    EXPECT_EQ(message, "--set camera.eye: line 1, column 257: nested deeper than 256 levels");
}

TEST(InputRules, DeeplyNestedJobFilesAreRefusedBeforeAnythingRecurses) {
    // Both crashed (stack overflow dumping the value) before the depth limit.
    auto dir = freshTempDir();
    auto set = writeFile(
        dir / "set.json",
        R"({"jobs": [{"scene": "a.json", "output": "a.exr", "set": {"camera.eye": )" + nestedArrays(50000) + "}}]}");
    EXPECT_TRUE(contains(jobError(set), set.string() + ": line 1, column ")) << jobError(set);
    EXPECT_TRUE(contains(jobError(set), ": nested deeper than 256 levels"));
    auto sweep = writeFile(dir / "sweep.json", R"([{"scene": "a.json", "output": "a{i}.exr",
        "sweep": {"path": "camera.eye", "values": [)" +
                                                   nestedObjects(50000) + "]}}]");
    EXPECT_TRUE(contains(jobError(sweep), ": nested deeper than 256 levels")) << jobError(sweep);
}

TEST(InputRules, DeeplyNestedGltfExtrasAreRefusedBeforeTinygltf) {
    auto dir = freshTempDir();
    GltfBuilder shallow;
    shallow.addMeshNode(shallow.triangle(), {{"extras", json::parse(nestedObjects(200))}});
    EXPECT_NO_THROW(loadScene(writeFile(dir / "shallow.gltf", shallow.gltf())));

    // Built as text: nlohmann's own dump would recurse 16k levels deep.
    GltfBuilder b;
    b.addMeshNode(b.triangle(), {{"extras", "DEEP"}});
    for (const char* name : {"deep.gltf", "deep.glb"}) {
        std::string text = std::string(name).ends_with(".glb") ? b.glb() : b.gltf();
        size_t at = text.find("\"DEEP\"");
        ASSERT_NE(at, std::string::npos);
        std::string deep = nestedObjects(16000);
        text.replace(at, 6, deep);
        if (text.starts_with("glTF")) {
            // Fix the JSON chunk's and the file's lengths (the chunk stays 4-byte aligned:
            // the nesting adds 4 * 16000 - 6 + 2 bytes).
            uint32_t chunk = 0, total = 0;
            std::memcpy(&chunk, text.data() + 12, 4);
            std::memcpy(&total, text.data() + 8, 4);
            uint32_t grow = uint32_t(deep.size() - 6);
            chunk += grow;
            total += grow;
            std::memcpy(text.data() + 12, &chunk, 4);
            std::memcpy(text.data() + 8, &total, 4);
        }
        auto file = writeFile(dir / name, text);
        std::string message = loadError(file);
        EXPECT_EQ(message.rfind(file.string() + ": line 1, column ", 0), 0u) << message;
        EXPECT_TRUE(contains(message, ": nested deeper than 256 levels")) << message;
    }
}

// --- duplicate keys ---------------------------------------------------------------------

TEST(InputRules, DuplicateKeysAreRefusedWithTheirPath) {
    auto dir = freshTempDir();
    auto film = writeFile(dir / "film.json", R"({"film": {"width": 10, "width": 20}})");
    EXPECT_EQ(loadError(film), film.string() + ": film: duplicate key \"width\"");
    auto root = writeFile(dir / "root.json", R"({"film": {}, "film": {}})");
    EXPECT_EQ(loadError(root), root.string() + ": duplicate key \"film\"");
    auto shape = writeFile(dir / "shape.json", R"({"shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1},
        {"type": "sphere", "center": [0,0,0], "radius": 1, "radius": 2}]})");
    EXPECT_EQ(loadError(shape), shape.string() + ": shapes[1]: duplicate key \"radius\"");

    auto plain = writeFile(dir / "plain.json", "{}");
    EXPECT_EQ(loadError(plain, {Override{"camera", R"({"fov_y": 30, "fov_y": 40})"}}),
              "--set camera: duplicate key \"fov_y\"");

    auto jobs =
        writeFile(dir / "jobs.json", R"({"jobs": [{"scene": "a.json", "output": "a.exr", "output": "b.exr"}]})");
    EXPECT_EQ(jobError(jobs), jobs.string() + ": jobs[0]: duplicate key \"output\"");

    GltfBuilder b;
    b.addMeshNode(b.triangle());
    std::string text = b.gltf();
    size_t at = text.find("\"scene\":0");
    ASSERT_NE(at, std::string::npos);
    text.insert(at, "\"scene\":0,");
    auto model = writeFile(dir / "dup.gltf", text);
    EXPECT_EQ(loadError(model), model.string() + ": duplicate key \"scene\"");
}

// --- glTF versions and integers ---------------------------------------------------------

TEST(InputRules, GltfOneIsRefused) {
    auto dir = freshTempDir();
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    b.doc["asset"]["version"] = "1.0";
    auto old = writeFile(dir / "old.gltf", b.gltf());
    EXPECT_EQ(loadError(old), old.string() + ": asset.version: \"1.0\" is not supported (glTF 2.x only)");
    b.doc.erase("asset");
    auto none = writeFile(dir / "none.gltf", b.gltf());
    EXPECT_EQ(loadError(none), none.string() + ": asset: missing (glTF 2.0 requires it)");

    GltfBuilder v;
    v.addMeshNode(v.triangle());
    std::string glb = v.glb();
    uint32_t one = 1;
    std::memcpy(glb.data() + 4, &one, 4);
    auto binary = writeFile(dir / "v1.glb", glb);
    EXPECT_EQ(loadError(binary), binary.string() + ": GLB container version 1 is not supported (glTF 2.0 only)");
}

TEST(InputRules, NonIntegralGltfIndicesAreRefusedNotTruncated) {
    auto dir = freshTempDir();
    GltfBuilder light;
    light.addMeshNode(light.triangle());
    light.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 1}},
                                                                {{"type", "point"}, {"intensity", 2}}};
    light.addNode({{"extensions", {{"KHR_lights_punctual", {{"light", 0.5}}}}}});
    auto half = writeFile(dir / "light.gltf", light.gltf());
    EXPECT_EQ(loadError(half),
              half.string() + ": nodes[1].extensions.KHR_lights_punctual.light: expected an integer, got 0.5");

    GltfBuilder mesh;
    mesh.addMeshNode(mesh.triangle());
    mesh.doc["nodes"][0]["mesh"] = 0.5;  // tinygltf read this as "no mesh"
    auto node = writeFile(dir / "mesh.gltf", mesh.gltf());
    EXPECT_EQ(loadError(node), node.string() + ": nodes[0].mesh: expected an integer, got 0.5");

    GltfBuilder attribute;
    attribute.addMeshNode(attribute.triangle());
    attribute.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 0.25;
    auto accessor = writeFile(dir / "attribute.gltf", attribute.gltf());
    EXPECT_EQ(loadError(accessor),
              accessor.string() + ": meshes[0].primitives[0].attributes.POSITION: expected an integer, got 0.25");

    // Integral values written as floats are integers; extras are the author's own.
    GltfBuilder fine;
    fine.addMeshNode(fine.triangle(), {{"extras", {{"mesh", 0.5}}}});
    fine.doc["nodes"][0]["mesh"] = 0.0;
    fine.doc["nodes"][0]["translation"] = {0.5, 0.25, 0};
    EXPECT_NO_THROW(loadScene(writeFile(dir / "fine.gltf", fine.gltf())));
}

// --- size cap and system errors -----------------------------------------------------------

TEST(InputRules, UnboundedAndOversizedFilesAreCapped) {
    try {
        // A device that never ends is not read at all: inputs are regular files.
        readInputFile("/dev/zero", "/dev/zero", 1 << 20);
        ADD_FAILURE() << "/dev/zero read";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "/dev/zero: cannot open file (not a regular file: a character device)");
    }
    // A sparse file one byte over the cap is refused by its size, before reading.
    auto big = freshTempDir() / "big.json";
    writeFile(big, "{}");
    fs::resize_file(big, kMaxJsonFileBytes + 1);
    EXPECT_EQ(loadError(big), big.string() + ": file too large (more than 1073741824 bytes)");
}

TEST(InputRules, ReadErrorsAndSymlinkLoopsSayWhatHappened) {
    // Reading /proc/self/mem at offset 0 fails with EIO (nothing is mapped there).
    EXPECT_EQ(loadError("/proc/self/mem"), "/proc/self/mem: read error: input/output error");
    auto dir = freshTempDir();
    fs::create_symlink(dir / "b.json", dir / "a.json");
    fs::create_symlink(dir / "a.json", dir / "b.json");
    EXPECT_EQ(loadError(dir / "a.json"),
              (dir / "a.json").string() + ": cannot open file (too many levels of symbolic links)");
    fs::create_symlink(dir / "loop.glb", dir / "loop.glb");
    EXPECT_EQ(loadError(dir / "loop.glb"),
              (dir / "loop.glb").string() + ": cannot open file (too many levels of symbolic links)");
}

// --- ranges -----------------------------------------------------------------------------

TEST(InputRules, RangesAreCheckedAtTheirLimits) {
    auto dir = freshTempDir();
    auto scene = [&](const std::string& shapes, const std::string& lights = "[]") {
        return writeFile(dir / "range.json", "{\"shapes\": " + shapes + ", \"lights\": " + lights + "}");
    };
    // Just inside: loads.
    EXPECT_NO_THROW(
        loadScene(scene(R"([{"type": "sphere", "center": [1e8, -1e8, 0], "radius": 1e8, "emission": 1e20}])",
                        R"([{"type": "point", "position": [0, 1e8, 0], "intensity": 1e20},
                                        {"type": "directional", "direction": [0, -1, 0], "irradiance": 1e20},
                                        {"type": "environment", "radiance": 1e20}])")));
    // Just outside (the next floats above 1e8 and 1e20): refused with the path.
    struct Case {
        std::string shapes, lights, expected;
    };
    const std::string sphere = R"("type": "sphere", "center": [0, 0, 0])";
    for (const Case& c : std::vector<Case>{
             {"[{" + sphere + R"(, "radius": 1.000001e8}])", "[]", "shapes[0].radius: must be at most 1e8"},
             {R"([{"type": "sphere", "center": [0, -1.000001e8, 0], "radius": 1}])", "[]",
              "shapes[0].center[1]: must be within [-1e8, 1e8]"},
             {R"([{"type": "quad", "origin": [0, 0, 0], "edge_u": [2e8, 0, 0], "edge_v": [0, 1, 0]}])", "[]",
              "shapes[0].edge_u[0]: must be within [-1e8, 1e8]"},
             {R"([{"type": "mesh", "positions": [0,0,0, 1,0,0, 0,1.000001e8,0], "indices": [0,1,2]}])", "[]",
              "shapes[0].positions[7]: must be within [-1e8, 1e8]"},
             {"[{" + sphere + R"(, "radius": 1, "emission": [1, 1.000001e20, 1]}])", "[]",
              "shapes[0].emission: radiance exceeds 1e20"},
             // P / (4 pi^2 r^2) with r = 1e-3, P = 1e16: 2.5e20.
             {"[{" + sphere + R"(, "radius": 1e-3, "power": 1e16}])", "[]",
              "shapes[0].power: the radiance from this power exceeds 1e20"},
             {"[]", R"([{"type": "point", "position": [0, 0, 0], "intensity": 1.000001e20}])",
              "lights[0].intensity: intensity exceeds 1e20"},
             {"[]", R"([{"type": "point", "position": [0, 0, 0], "power": 1.3e21}])",
              "lights[0].power: intensity exceeds 1e20"},
             {"[]", R"([{"type": "point", "position": [0, 0, 1.000001e8], "power": 1}])",
              "lights[0].position[2]: must be within [-1e8, 1e8]"},
             {"[]", R"([{"type": "directional", "direction": [0, -1, 0], "irradiance": 1.000001e20}])",
              "lights[0].irradiance: irradiance exceeds 1e20"},
             {"[]", R"([{"type": "environment", "radiance": 1.000001e20}])",
              "lights[0].radiance: radiance exceeds 1e20"},
         }) {
        auto file = scene(c.shapes, c.lights);
        EXPECT_EQ(loadError(file), file.string() + ": " + c.expected + " (README: ranges)") << c.shapes << c.lights;
    }
    auto camera = writeFile(dir / "camera.json", R"({"camera": {"eye": [0, 0, 1.000001e8]}})");
    EXPECT_EQ(loadError(camera), camera.string() + ": camera.eye[2]: must be within [-1e8, 1e8] (README: ranges)");

    GltfBuilder far;
    far.addMeshNode(far.triangle(), {{"translation", {0, 2e8, 0}}});
    auto model = writeFile(dir / "far.gltf", far.gltf());
    EXPECT_EQ(loadError(model),
              model.string() +
                  ": meshes[0].primitives[0].attributes.POSITION: vertex 0 is not within [-1e8, 1e8] (README: ranges)");
}

// A sphere of the largest radius, seen from the far end of the range, emitting the largest
// radiance: every camera ray hits it (it fills a 30-degree cone, the view 20 degrees), so
// every pixel is exactly that radiance, summed over 16 samples without overflow. (With
// radius 1e20, accepted before, no ray hit the sphere.)
TEST(InputRules, SphereOfMaximumRadiusAndRadianceRendersExactly) {
    json scene = {
        {"camera", {{"eye", {0, 0, 1e8}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_y", 40}}},
        {"film", {{"width", 8}, {"height", 8}}},
        {"sampler", {{"spp", 16}}},
        // Black, so that what the camera sees is the emission alone.
        {"materials", {{"black", {{"albedo", 0}}}}},
        {"shapes",
         {{{"type", "sphere"}, {"center", {0, 0, -1e8}}, {"radius", 1e8}, {"emission", 1e20}, {"material", "black"}}}},
    };
    Image image = test::renderJson(scene, "input_rules_max_sphere");
    ASSERT_EQ(image.width * image.height, 64u);
    for (size_t i = 0; i < 64; ++i)
        for (int c = 0; c < 3; ++c) {
            float value = image.rgb[i * 3 + c];
            ASSERT_TRUE(std::isfinite(value)) << "pixel " << i;
            EXPECT_NEAR(value / 1e20, 1.0, 1e-6) << "pixel " << i << " channel " << c;
        }
}

// --- glTF file access -------------------------------------------------------------------

TEST(InputRules, GltfReadsOnlyFilesInsideTheModelFolder) {
    auto dir = freshTempDir();
    fs::create_directories(dir / "model" / "data");
    GltfBuilder b;
    b.addMeshNode(b.triangle());
    std::string bin(b.bin.begin(), b.bin.end());
    writeFile(dir / "outside.bin", bin);
    writeFile(dir / "model" / "data" / "inside.bin", bin);
    fs::create_symlink(dir / "outside.bin", dir / "model" / "link.bin");
    auto withBuffer = [&](const std::string& name, const std::string& uri) {
        json doc = b.doc;
        doc["buffers"] = {{{"byteLength", b.bin.size()}, {"uri", uri}}};
        return writeFile(dir / "model" / name, doc.dump());
    };

    EXPECT_NO_THROW(loadScene(withBuffer("inside.gltf", "data/inside.bin")));
    EXPECT_NO_THROW(loadScene(withBuffer("dotted.gltf", "data/../data/inside.bin")));
    for (const std::string& uri :
         {std::string("../outside.bin"), (dir / "outside.bin").string(), std::string("link.bin")}) {
        auto file = withBuffer("refused.gltf", uri);
        EXPECT_EQ(loadError(file), file.string() + ": refusing to read \"" + uri +
                                       "\": it is outside the model's folder (--allow-any-path reads it)");
    }
    // Images are read (not decoded) by tinygltf as well.
    json image = b.doc;
    image["buffers"] = {{{"byteLength", b.bin.size()}, {"uri", "data/inside.bin"}}};
    image["images"] = {{{"uri", "../../../../../../../etc/passwd"}}};
    auto withImage = writeFile(dir / "model" / "image.gltf", image.dump());
    EXPECT_TRUE(contains(loadError(withImage), ": refusing to read \"../../../../../../../etc/passwd\""))
        << loadError(withImage);

    // A scene may name models only inside its own folder too.
    auto scene =
        writeFile(dir / "model" / "data" / "scene.json", R"({"shapes": [{"type": "gltf", "file": "../inside.gltf"}]})");
    EXPECT_EQ(loadError(scene),
              scene.string() +
                  ": shapes[0].file: refusing to read \"../inside.gltf\": it is outside the scene's folder "
                  "(--allow-any-path reads it)");

    AllowAnyPath allow;
    EXPECT_NO_THROW(loadScene(withBuffer("outside.gltf", "../outside.bin")));
    EXPECT_NO_THROW(loadScene(scene));
}

TEST(InputRules, ErrorMessagesDoNotEchoFileContents) {
    auto dir = freshTempDir();
    // nlohmann's message quoted the string it was reading: "last read: '\"SECRET-PASSWORD'".
    auto scene = writeFile(dir / "secret.json", "{\"film\": \"SECRET-PASSWORD");
    EXPECT_EQ(loadError(scene), scene.string() +
                                    ": line 1, column 26: syntax error while parsing value - "
                                    "invalid string: missing closing quote");
    auto model = writeFile(dir / "secret.gltf", "{\"asset\": \"SECRET-PASSWORD");
    EXPECT_FALSE(contains(loadError(model), "SECRET")) << loadError(model);
    auto jobs = writeFile(dir / "jobs.json", "[{\"scene\": \"SECRET-PASSWORD");
    EXPECT_FALSE(contains(jobError(jobs), "SECRET")) << jobError(jobs);
    auto literal = writeFile(dir / "literal.json", "nullSECRET");
    EXPECT_FALSE(contains(loadError(literal), "last read")) << loadError(literal);
}

// --- linear parsing -----------------------------------------------------------------------

// Each JSON path used to be kept as text for every value read and nlohmann's callback
// parser rescanned the parent array after each object (200k lights: 9 s). Now a path is
// only turned into text for a message: loading builds none, and the error still names it.
TEST(InputRules, JsonPathsAreBuiltOnlyForMessages) {
    const size_t lights = 200000;
    std::string text = "{\"lights\": [";
    for (size_t i = 0; i < lights; ++i)
        text += std::string(i ? "," : "") + "{\"type\": \"point\", \"position\": [" + std::to_string(i % 7) +
                ", 1, 2], \"power\": 1}";
    auto dir = freshTempDir();
    auto good = writeFile(dir / "lights.json", text + "]}");
    size_t before = jsonPathTextCount();
    Scene scene = loadScene(good);
    EXPECT_EQ(scene.lights.size(), lights);
    EXPECT_EQ(jsonPathTextCount(), before);

    size_t last = text.rfind("1, 2]");
    text.replace(last, 1, "\"x\"");
    auto bad = writeFile(dir / "bad.json", text + "]}");
    EXPECT_EQ(loadError(bad), bad.string() + ": lights[199999].position[1]: expected a number, got a string");
    EXPECT_GT(jsonPathTextCount(), before);
}

// --- the command line ---------------------------------------------------------------------

TEST(InputRules, CommandLineRefusesBadInputsWithExitTwo) {
    auto dir = freshTempDir();
    auto expectRefused = [](const std::string& args, const std::string& mention) {
        std::string err;
        EXPECT_EQ(test::runPenumbra(args, &err), 2) << args << ": " << err;
        EXPECT_TRUE(contains(err, mention)) << args << ": " << err;
        EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line: " << err;
    };
    auto jobs = writeFile(dir / "deep_jobs.json", R"([{"scene": "a.json", "output": "a.exr", "set": {"camera.eye": )" +
                                                      nestedArrays(50000) + "}}]");
    expectRefused("batch --list '" + jobs.string() + "'", "nested deeper than 256 levels");

    GltfBuilder b;
    b.addMeshNode(b.triangle(), {{"extras", "DEEP"}});
    std::string text = b.gltf();
    text.replace(text.find("\"DEEP\""), 6, nestedObjects(16000));
    auto model = writeFile(dir / "deep.gltf", text);
    auto out = dir / "out.exr";
    expectRefused("render '" + model.string() + "' -o '" + out.string() + "' --quiet", "nested deeper than 256 levels");
    expectRefused("render /dev/zero -o '" + out.string() + "' --quiet",
                  "/dev/zero: cannot open file (not a regular file");

    // A buffer outside the model's folder: refused by default, read with --allow-any-path.
    fs::create_directories(dir / "model");
    writeFile(dir / "outside.bin", std::string(b.bin.begin(), b.bin.end()));
    json doc = b.doc;
    doc["nodes"][0].erase("extras");
    doc["buffers"] = {{{"byteLength", b.bin.size()}, {"uri", "../outside.bin"}}};
    auto outsider = writeFile(dir / "model" / "outsider.gltf", doc.dump());
    std::string args = "render '" + outsider.string() + "' -o '" + out.string() +
                       "' --quiet --width 4 --height 4 --spp 1";
    expectRefused(args, "refusing to read \"../outside.bin\"");
    EXPECT_FALSE(fs::exists(out));
    std::string err;
    EXPECT_EQ(test::runPenumbra(args + " --allow-any-path", &err), 0) << err;
    EXPECT_TRUE(fs::exists(out));
}
