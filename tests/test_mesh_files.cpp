// Mesh files (SCENE_FORMAT.md "Mesh files", host/scene/mesh_file.h): PLY in ASCII and both
// binary byte orders and OBJ in every index form give the triangles of the equivalent JSON
// mesh; usemtl picks scene materials; bad files are refused naming the file and the line
// (OBJ) or element (PLY); a PLY renders bit for bit as the same JSON mesh.
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/input_file.h"
#include "gpu_fixture.h"
#include "render_helpers.h"
#include "scene/load.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

fs::path freshDir(const std::string& name) { return test::freshOutputDir("mesh-files", name); }

void writeFile(const fs::path& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

// The shortest decimal text of the values below ("0", "1.5"), which read back exactly.
std::string num(float x) {
    std::ostringstream out;
    out << x;
    return out.str();
}

// A bent strip of two quads (six vertices), with normals and uvs: the reference mesh.
// Values are exact in float and in decimal text, so every file spells them exactly.
const std::vector<float> kPositions = {0, 0, 0, 1, 0, 0, 2, 0.5f, 0, 0, 1, 0, 1, 1, 0, 2, 1.5f, 0};
const std::vector<float> kNormals = {0, 0, 1, 0, 0.5f, 1, 0, 1, 1, 0, 0, 1, 0, 0.5f, 1, 0, 1, 1};
const std::vector<float> kUvs = {0, 0, 0.5f, 0, 1, 0, 0, 1, 0.5f, 1, 1, 1};  // as in the file (v up)
const std::vector<std::vector<uint32_t>> kQuads = {{0, 1, 4, 3}, {1, 2, 5, 4}};

// The JSON mesh the files stand for: quads fanned from their first corner, uvs flipped.
json jsonMesh(bool normals, bool uvs) {
    std::vector<uint32_t> indices;
    for (const auto& q : kQuads) indices.insert(indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    json mesh = {{"type", "mesh"}, {"positions", kPositions}, {"indices", indices}};
    if (normals) mesh["normals"] = kNormals;
    if (uvs) {
        std::vector<float> flipped = kUvs;
        for (size_t i = 1; i < flipped.size(); i += 2) flipped[i] = 1.0f - flipped[i];
        mesh["uvs"] = flipped;
    }
    return mesh;
}

json sceneWith(const json& shape) {
    return {{"film", {{"width", 16}, {"height", 12}}},
            {"sampler", {{"spp", 4}}},
            {"camera", {{"eye", {1, 0.75, 4}}, {"target", {1, 0.75, 0}}}},
            {"materials", {{"red", {{"type", "diffuse"}, {"albedo", {0.8, 0.1, 0.1}}}}}},
            {"shapes", {shape}},
            {"lights", {{{"type", "point"}, {"position", {1, 1, 3}}, {"power", 40}}}}};
}

Scene loadIn(const fs::path& dir, const json& doc, const std::string& name = "scene.json") {
    std::ofstream(dir / name) << doc.dump();
    return loadScene(dir / name);
}

// One triangle's three corners: position, normal (0 when none), uv (0 when none).
struct Corner {
    glm::vec3 p, n;
    glm::vec2 uv;
    bool operator==(const Corner&) const = default;
};

std::vector<Corner> triangles(const Shape& s) {
    std::vector<Corner> out;
    for (uint32_t i : s.indices)
        out.push_back(
            {s.positions[i], s.normals.empty() ? glm::vec3(0) : s.normals[i], s.uvs.empty() ? glm::vec2(0) : s.uvs[i]});
    return out;
}

// The file's triangles equal the JSON mesh's, corner by corner and bit for bit.
void expectSameTriangles(const fs::path& dir, const std::string& file, bool normals, bool uvs) {
    SCOPED_TRACE(file);
    Scene fromFile = loadIn(dir, sceneWith({{"type", "mesh"}, {"file", file}}), "file.json");
    Scene fromJson = loadIn(dir, sceneWith(jsonMesh(normals, uvs)), "json.json");
    ASSERT_EQ(fromFile.shapes.size(), 1u);
    ASSERT_EQ(fromJson.shapes.size(), 1u);
    const Shape &a = fromFile.shapes[0], &b = fromJson.shapes[0];
    EXPECT_EQ(a.normals.empty(), b.normals.empty());
    EXPECT_EQ(a.uvs.empty(), b.uvs.empty());
    EXPECT_TRUE(triangles(a) == triangles(b));
}

std::string objText(const std::string& faceForm) {
    std::string t = "# the reference strip\n";
    for (size_t v = 0; v < 6; ++v)
        t += "v " + num(kPositions[3 * v]) + " " + num(kPositions[3 * v + 1]) + " " + num(kPositions[3 * v + 2]) + "\n";
    for (size_t v = 0; v < 6; ++v)
        t += "vn " + num(kNormals[3 * v]) + " " + num(kNormals[3 * v + 1]) + " " + num(kNormals[3 * v + 2]) + "\n";
    for (size_t v = 0; v < 6; ++v) t += "vt " + num(kUvs[2 * v]) + " " + num(kUvs[2 * v + 1]) + "\n";
    t += "g strip\ns 1\n";
    for (const auto& q : kQuads) {
        t += "f";
        for (uint32_t i : q) {
            const std::string pos = std::to_string(i + 1), neg = std::to_string(int(i) - 6);
            if (faceForm == "v") t += " " + pos;
            if (faceForm == "v/vt") t += " " + pos + "/" + pos;
            if (faceForm == "v//vn") t += " " + pos + "//" + pos;
            if (faceForm == "v/vt/vn") t += " " + pos + "/" + pos + "/" + pos;
            if (faceForm == "negative") t += " " + neg + "/" + neg + "/" + neg;
        }
        t += "\n";
    }
    return t;
}

enum class PlyFormat { Ascii, Little, Big };

template <class T>
void put(std::string& out, T value, bool big) {
    char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    if (big == (std::endian::native == std::endian::little)) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
}

// The reference strip as PLY, with an extra vertex property and an extra element to read past.
std::string plyText(PlyFormat format, bool normals, bool uvs) {
    const char* name = format == PlyFormat::Ascii    ? "ascii"
                       : format == PlyFormat::Little ? "binary_little_endian"
                                                     : "binary_big_endian";
    std::string t = std::string("ply\nformat ") + name + " 1.0\ncomment reference strip\nelement vertex 6\n" +
                    "property float x\nproperty float y\nproperty float z\nproperty uchar red\n";
    if (normals) t += "property float nx\nproperty float ny\nproperty float nz\n";
    if (uvs) t += "property float s\nproperty float t\n";
    t += "element face 2\nproperty list uchar int vertex_indices\nelement note 1\nproperty double weight\nend_header\n";
    const bool big = format == PlyFormat::Big;
    for (size_t v = 0; v < 6; ++v) {
        std::vector<float> values = {kPositions[3 * v], kPositions[3 * v + 1], kPositions[3 * v + 2]};
        std::vector<float> more;
        if (normals) more.insert(more.end(), {kNormals[3 * v], kNormals[3 * v + 1], kNormals[3 * v + 2]});
        if (uvs) more.insert(more.end(), {kUvs[2 * v], kUvs[2 * v + 1]});
        if (format == PlyFormat::Ascii) {
            for (float x : values) t += num(x) + " ";
            t += "200";
            for (float x : more) (t += ' ') += num(x);
            t += "\n";
        } else {
            for (float x : values) put(t, x, big);
            put(t, uint8_t(200), big);
            for (float x : more) put(t, x, big);
        }
    }
    for (const auto& q : kQuads) {
        if (format == PlyFormat::Ascii) {
            t += "4";
            for (uint32_t i : q) (t += ' ') += std::to_string(i);
            t += "\n";
        } else {
            put(t, uint8_t(4), big);
            for (uint32_t i : q) put(t, int32_t(i), big);
        }
    }
    if (format == PlyFormat::Ascii) t += "0.5\n";
    else put(t, 0.5, big);
    return t;
}

// loadScene of a scene whose only shape is {"type": "mesh", "file": NAME} with `bytes` as
// the file must fail with an InputError containing every one of `needles`.
void expectRefused(const fs::path& dir, const std::string& name, const std::string& bytes,
                   const std::vector<std::string>& needles) {
    SCOPED_TRACE(name);
    writeFile(dir / name, bytes);
    try {
        loadIn(dir, sceneWith({{"type", "mesh"}, {"file", name}}));
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        for (const std::string& n : needles) EXPECT_NE(message.find(n), std::string::npos) << message << " / " << n;
    }
}

}  // namespace

TEST(MeshFiles, ObjInEveryIndexFormGivesTheJsonTriangles) {
    const fs::path dir = freshDir("obj-forms");
    for (const auto& [form, normals, uvs] :
         std::vector<std::tuple<std::string, bool, bool>>{{"v", false, false},
                                                          {"v/vt", false, true},
                                                          {"v//vn", true, false},
                                                          {"v/vt/vn", true, true},
                                                          {"negative", true, true}}) {
        const std::string name = "strip-" + std::string(form == "negative" ? "neg" : std::to_string(form.size())) +
                                 ".obj";
        writeFile(dir / name, objText(form));
        expectSameTriangles(dir, name, normals, uvs);
    }
}

TEST(MeshFiles, PlyAsciiAndBothBinaryOrdersGiveTheJsonTriangles) {
    const fs::path dir = freshDir("ply-formats");
    int n = 0;
    for (PlyFormat format : {PlyFormat::Ascii, PlyFormat::Little, PlyFormat::Big})
        for (auto [normals, uvs] : {std::pair{true, true}, std::pair{false, false}, std::pair{true, false}}) {
            const std::string name = "strip-" + std::to_string(n++) + ".ply";
            writeFile(dir / name, plyText(format, normals, uvs));
            expectSameTriangles(dir, name, normals, uvs);
        }
}

TEST(MeshFiles, UsemtlPicksSceneMaterialsElseTheShapesOwn) {
    const fs::path dir = freshDir("usemtl");
    writeFile(dir / "parts.obj",
              "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
              "f 1 2 3\n"              // before any usemtl: the shape's own material
              "usemtl red\nf 2 4 3\n"  // a scene material
              "usemtl nosuch\nf 1 2 4\n"
              "usemtl red\nf 1 4 3\n");  // red again joins the first red part
    json shape = {{"type", "mesh"}, {"file", "parts.obj"}, {"material", "own"}, {"power", 10}};
    json doc = sceneWith(shape);
    doc["materials"]["own"] = {{"type", "diffuse"}, {"albedo", {0.2, 0.2, 0.2}}};
    Scene scene = loadIn(dir, doc);
    ASSERT_EQ(scene.shapes.size(), 3u);
    auto materialName = [&](const Shape& s) { return scene.materials[s.material].name; };
    EXPECT_EQ(materialName(scene.shapes[0]), "own");
    EXPECT_EQ(materialName(scene.shapes[1]), "red");
    EXPECT_EQ(scene.shapes[1].indices.size(), 6u);
    EXPECT_EQ(materialName(scene.shapes[2]), "own");
    // The power spreads over all parts: four triangles of area 1/2, Le = P / (pi A).
    for (const Shape& s : scene.shapes) EXPECT_FLOAT_EQ(s.emission.x, 10.0f / (float(M_PI) * 2.0f));
}

TEST(MeshFiles, BadObjFilesNameTheFileAndLine) {
    const fs::path dir = freshDir("bad-obj");
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    expectRefused(dir, "range.obj", tri + "f 1 2 4\n", {"range.obj: line 4:", "out of range"});
    expectRefused(dir, "zero.obj", tri + "f 0 1 2\n", {"zero.obj: line 4:", "out of range"});
    expectRefused(dir, "negative.obj", tri + "f -1 -2 -4\n", {"negative.obj: line 4:", "out of range"});
    expectRefused(dir, "vt.obj", tri + "vt 0 0\nf 1/1 2/2 3/1\n", {"vt.obj: line 5:", "texture coordinate (vt)"});
    expectRefused(dir, "number.obj", "v 0 0 0\nv 1 x 0\n", {"number.obj: line 2:", "\"x\" is not a finite number"});
    expectRefused(dir, "huge.obj", "v 0 0 1e9\n", {"huge.obj: line 1:", "[-1e8, 1e8]"});
    expectRefused(dir, "inf.obj", "v 0 0 1e999\n", {"inf.obj: line 1:"});
    expectRefused(dir, "two.obj", tri + "f 1 2\n", {"two.obj: line 4:", "at least 3"});
    expectRefused(dir, "flat.obj", tri + "v 2 0 0\nf 1 2 4\n", {"flat.obj: line 5:", "zero or non-finite area"});
    expectRefused(dir, "curve.obj", tri + "curv 0 1 1 2\n", {"curve.obj: line 4:", "unsupported statement \"curv\""});
    expectRefused(dir, "mixed.obj", tri + "vn 0 0 1\nf 1//1 2//1 3//1\nf 1 2 3\n", {"mixed.obj: line 6:", "normals"});
    expectRefused(dir, "zeronormal.obj", tri + "vn 0 0 0\nf 1//1 2//1 3//1\n",
                  {"zeronormal.obj: line 5:", "zero length"});
    expectRefused(dir, "form.obj", tri + "f 1// 2// 3//\n", {"form.obj: line 4:"});
    expectRefused(dir, "empty.obj", tri, {"empty.obj:", "no faces"});
}

TEST(MeshFiles, BadPlyFilesNameTheFileAndElement) {
    const fs::path dir = freshDir("bad-ply");
    const std::string good = plyText(PlyFormat::Ascii, false, false);
    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string t = good;
        t.replace(t.find(from), from.size(), to);
        return t;
    };
    expectRefused(dir, "range.ply", replaced("4 1 2 5 4", "4 1 2 6 4"), {"range.ply: face 1:", "out of range"});
    expectRefused(dir, "position.ply", replaced("0 1 0 200", "0 1e9 0 200"), {"position.ply: vertex 3:", "[-1e8"});
    expectRefused(dir, "word.ply", replaced("0 1 0 200", "0 one 0 200"), {"word.ply: vertex 3:", "\"one\""});
    expectRefused(dir, "type.ply", replaced("property float y", "property float3 y"),
                  {"type.ply: header line 6:", "unknown property type \"float3\""});
    expectRefused(dir, "count.ply", replaced("element vertex 6", "element vertex 60000000000"),
                  {"count.ply: header:", "claims 60000000000"});
    expectRefused(dir, "nox.ply", replaced("property float x", "property float w"), {"nox.ply: header:", "x, y and z"});
    expectRefused(dir, "magic.ply", "plx\n" + good.substr(4), {"magic.ply: header:", "not a PLY file"});
    expectRefused(dir, "format.ply", replaced("ascii 1.0", "ascii 2.0"), {"format.ply: header line 2:", "version"});
    expectRefused(dir, "flat.ply", replaced("4 1 2 5 4", "3 1 1 2"), {"flat.ply: face 1:", "zero or non-finite area"});
    expectRefused(dir, "short.ply", replaced("4 1 2 5 4", "2 1 2"), {"short.ply: face 1:", "at least 3"});
    const std::string binary = plyText(PlyFormat::Little, true, true);
    expectRefused(dir, "truncated.ply", binary.substr(0, binary.size() - 20),
                  {"truncated.ply: face 1:", "ends inside"});
    expectRefused(dir, "noheader.ply", "ply\nformat ascii 1.0\nelement vertex 1\n",
                  {"noheader.ply: header:", "end_header"});
}

TEST(MeshFiles, FileAndInlineDataTogetherAreRefusedWithTheJsonPath) {
    const fs::path dir = freshDir("both");
    writeFile(dir / "strip.obj", objText("v"));
    json shape = jsonMesh(false, false);
    shape["file"] = "strip.obj";
    try {
        loadIn(dir, sceneWith(shape));
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("scene.json: shapes[0].positions: a mesh with \"file\""),
                  std::string::npos)
            << e.what();
    }
    // Other extensions are not mesh files.
    writeFile(dir / "strip.stl", objText("v"));
    expectRefused(dir, "strip.stl", objText("v"), {"strip.stl: not a mesh file"});
}

TEST(MeshFiles, FilesOutsideTheScenesFolderNeedAllowAnyPath) {
    const fs::path dir = freshDir("confined");
    fs::create_directories(dir / "scene");
    writeFile(dir / "outside.obj", objText("v"));
    const json doc = sceneWith({{"type", "mesh"}, {"file", "../outside.obj"}});
    try {
        loadIn(dir / "scene", doc);
        ADD_FAILURE() << "read a file outside the scene's folder";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("shapes[0].file: refusing to read \"../outside.obj\""), std::string::npos)
            << e.what();
    }
    setAllowAnyPath(true);
    EXPECT_NO_THROW(loadIn(dir / "scene", doc));
    setAllowAnyPath(false);
    // A missing file is an error naming the field.
    try {
        loadIn(dir, sceneWith({{"type", "mesh"}, {"file", "missing.ply"}}));
        ADD_FAILURE() << "accepted a missing file";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("shapes[0].file: cannot open"), std::string::npos) << e.what();
    }
}

TEST(MeshFiles, BadMeshFileExitsTwoWithOneLine) {
    const fs::path dir = freshDir("cli");
    writeFile(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    std::ofstream(dir / "scene.json") << sceneWith({{"type", "mesh"}, {"file", "bad.obj"}}).dump();
    std::string err;
    EXPECT_EQ(test::runPenumbra("render " + test::shellQuoted(dir / "scene.json") + " --quiet -o " +
                                    test::shellQuoted(dir / "out.exr"),
                                &err),
              2);
    EXPECT_NE(err.find("bad.obj: line 4: vertex (v) index 9 out of range"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
}

TEST(MeshFiles, PlyRendersBitForBitAsTheJsonMesh) {
    const fs::path dir = freshDir("render");
    writeFile(dir / "strip.ply", plyText(PlyFormat::Big, true, true));
    const Image fromFile =
        test::renderScene(loadIn(dir, sceneWith({{"type", "mesh"}, {"file", "strip.ply"}}), "f.json"));
    const Image fromJson = test::renderScene(loadIn(dir, sceneWith(jsonMesh(true, true)), "j.json"));
    ASSERT_EQ(fromFile.rgb.size(), fromJson.rgb.size());
    EXPECT_TRUE(fromFile.rgb == fromJson.rgb);
    double sum = 0;
    for (float v : fromFile.rgb) sum += v;
    EXPECT_GT(sum, 0.0) << "the strip must be lit for the comparison to mean anything";
}
