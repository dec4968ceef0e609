// glTF normal maps on lavapipe: a quad x, z in [0, 1] at y = 0 facing up (+y), uv (x, z), a
// rough pbr material and a 4 x 4 normal map whose texels all encode one tilted tangent-space
// normal, lit by a directional light and seen from above (render_helpers.h, topDownCamera).
//
// In glTF's tangent frame T = dp/du = +x, N = +y and B = w cross(N, T): with the file's
// TANGENT (1, 0, 0, 1), B = -z, the direction of decreasing v, the image's "up" that a normal
// map's +Y (green) points along (glTF 2.0 section 3.9.3). The shading normal is then
// normalize(c.x T + c.y B + c.z N) with c = (2 rgb - 1) (scale, scale, 1) decoded from the
// PNG's bytes, and the image the pbr BRDF (pbr_reference.h) at that normal times the light's
// intensity over the squared distance times cos between the light and that normal: a
// closed form per plane point. A point light (not a directional one) so that radiance varies
// across each pixel: the pixel samples' spread then bounds the estimate, not float rounding.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/packing.hpp>
#include <nlohmann/json.hpp>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#include "gltf_builder.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "pbr_reference.h"
#include "render/kernel_options.h"
#include "render/scene_arrays.h"
#include "render_helpers.h"
#include "scene/load.h"
#include "scene/tangents.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr double kIntensity = 2.0;
const glm::dvec3 kBase{0.6, 0.6, 0.6};
// Above the quad, off towards -x and +z so that a tilt of the normal along x or along z
// changes cos (and so the picture).
const glm::dvec3 kLight{0.1, 0.8, 0.9};

// A 4 x 4 RGB PNG whose every texel is `rgb`.
void writeConstantPng(const std::filesystem::path& file, glm::u8vec3 rgb) {
    std::vector<uint8_t> pixels;
    for (int i = 0; i < 16; ++i) pixels.insert(pixels.end(), {rgb.x, rgb.y, rgb.z});
    ASSERT_NE(stbi_write_png(file.string().c_str(), 4, 4, 3, pixels.data(), 4 * 3), 0);
}

// The bytes that encode unit tangent-space normal n: round(255 (n + 1) / 2).
glm::u8vec3 encode(glm::dvec3 n) {
    glm::dvec3 b = glm::round(255.0 * (n + 1.0) / 2.0);
    return glm::u8vec3(uint8_t(b.x), uint8_t(b.y), uint8_t(b.z));
}

struct QuadOptions {
    bool normalMap = true;
    glm::u8vec3 texel{128, 128, 255};
    double scale = 1.0;
    bool tangents = true;     // write a TANGENT attribute (else the renderer computes them)
    bool swappedUvs = false;  // uv (z, x), a mirrored mapping, instead of (x, z)
};

// The quad's glTF, its normal map written beside it as normal.png.
std::string normalMappedQuad(const std::filesystem::path& dir, const QuadOptions& o) {
    writeConstantPng(dir / "normal.png", o.texel);
    test::GltfBuilder b;
    std::vector<float> normals = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
    std::vector<float> uvs = {0, 0, 1, 0, 1, 1, 0, 1};
    // The frame the file gives: T = dp/du, and w such that w cross(N, T) = -dp/dv.
    std::vector<float> tangents = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
    if (o.swappedUvs) {
        uvs = {0, 0, 0, 1, 1, 1, 1, 0};                                   // (z, x)
        tangents = {0, 0, 1, -1, 0, 0, 1, -1, 0, 0, 1, -1, 0, 0, 1, -1};  // T = +z, B = -x
    }
    json attributes = {{"POSITION", b.positions({0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1})},
                       {"NORMAL", b.addAccessor(normals.data(), normals.size() * 4, 5126, 4, "VEC3")},
                       {"TEXCOORD_0", b.addAccessor(uvs.data(), uvs.size() * 4, 5126, 4, "VEC2")}};
    if (o.tangents) attributes["TANGENT"] = b.addAccessor(tangents.data(), tangents.size() * 4, 5126, 4, "VEC4");
    // Counter-clockwise seen from +y: cross(p3 - p0, p2 - p0) = +y.
    b.addMeshNode({{"attributes", attributes}, {"indices", b.indices({0, 3, 2, 0, 2, 1})}, {"material", 0}});
    json material = {
        {"pbrMetallicRoughness",
         {{"baseColorFactor", {kBase.x, kBase.y, kBase.z, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0.6}}}};
    if (o.normalMap) {
        material["normalTexture"] = {{"index", 0}};
        if (o.scale != 1.0) material["normalTexture"]["scale"] = o.scale;
        b.doc["textures"] = {{{"source", 0}}};
        b.doc["images"] = {{{"uri", "normal.png"}}};
    }
    b.doc["materials"] = {material};
    return b.gltf();
}

json quadScene(int spp) {
    return {
        {"camera", test::topDownCamera(0.5, 0.5, 0.5)},
        {"film", {{"width", 64}, {"height", 64}}},
        {"sampler", {{"spp", spp}, {"seed", 5}, {"type", "independent"}}},
        {"integrator", {{"type", "direct"}, {"strategy", "mis"}}},
        {"shapes", json::array({{{"type", "gltf"}, {"file", "quad.gltf"}}})},
        {"lights",
         json::array({{{"type", "point"}, {"position", {kLight.x, kLight.y, kLight.z}}, {"intensity", kIntensity}}})}};
}

// The shading normal the texel's bytes give in the quad's frame (T = +x, B = -z, N = +y).
// The GPU holds texels as half floats (shared/types.h, "Textures"): byte / 255 rounded so.
glm::dvec3 bentNormal(glm::u8vec3 texel, double scale) {
    auto half = [](int byte) { return double(glm::unpackHalf1x16(glm::packHalf1x16(float(byte) / 255.0f))); };
    glm::dvec3 c = 2.0 * glm::dvec3(half(texel.x), half(texel.y), half(texel.z)) - 1.0;
    c.x *= scale;
    c.y *= scale;
    return glm::normalize(c.x * glm::dvec3(1, 0, 0) + c.y * glm::dvec3(0, 0, -1) + c.z * glm::dvec3(0, 1, 0));
}

// Radiance towards the top-down camera's eye (at height 50 over the patch centre) from plane
// point x shaded with normal n.
double closedForm(glm::dvec3 x, glm::dvec3 n) {
    const glm::dvec3 wo = glm::normalize(glm::dvec3(0.5, 50.0, 0.5) - x);
    test::PbrParams p;
    p.baseColor = kBase;
    p.roughness = 0.6;
    const glm::dvec3 d = kLight - x, wi = glm::normalize(d);
    return test::pbrF(p, n, wo, wi).x * kIntensity * std::max(0.0, glm::dot(n, wi)) / glm::dot(d, d);
}

Image renderQuad(const std::string& name, const QuadOptions& o, int spp) {
    auto dir = test::freshOutputDir("gltf-normal-map", name);
    test::writeFile(dir / "quad.gltf", normalMappedQuad(dir, o));
    return test::renderScene(test::sceneFromJson(quadScene(spp), "gltf-normal-map/" + name + "/scene"));
}

}  // namespace

// A constant tilted normal map (30 degrees from N, towards +T and +B at 60 degrees around N,
// scale 0.8) against the closed form of its bent normal; light and MIS estimators alike.
TEST(GltfNormalMap, TiltedMapHasTheClosedFormOfItsNormal) {
    const double a = 30.0 * M_PI / 180.0, phi = 60.0 * M_PI / 180.0;
    QuadOptions o;
    o.texel = encode({std::sin(a) * std::cos(phi), std::sin(a) * std::sin(phi), std::cos(a)});
    o.scale = 0.8;
    const glm::dvec3 n = bentNormal(o.texel, o.scale);
    auto dir = test::freshOutputDir("gltf-normal-map", "tilted");
    test::writeFile(dir / "quad.gltf", normalMappedQuad(dir, o));
    // The tilt changes the picture by far more than the test resolves: without it the
    // expectation is a different one (checked here so that a weak test cannot pass).
    ASSERT_GT(std::fabs(closedForm({0.5, 0, 0.5}, n) - closedForm({0.5, 0, 0.5}, {0, 1, 0})), 0.05);
    test::expectTopDownMatches(
        quadScene(64), {{{"type", "direct"}, {"strategy", "light"}}, {{"type", "direct"}, {"strategy", "mis"}}},
        [&](glm::dvec3 x) { return closedForm(x, n); }, "gltf-normal-map/tilted/scene", 1e-4);
}

// A flat map at scale 0 decodes to exactly (0, 0, 1): the bent normal is N bit for bit, and so
// is the image of the same quad without a normal map (same seed, same random numbers).
TEST(GltfNormalMap, FlatMapRendersAsWithoutOne) {
    QuadOptions flat;
    flat.texel = {255, 0, 255};  // x and y are multiplied by the scale 0
    flat.scale = 0.0;
    QuadOptions none;
    none.normalMap = false;
    Image a = renderQuad("flat", flat, 8), b = renderQuad("none", none, 8);
    EXPECT_EQ(a.rgb, b.rgb);
}

// The file's TANGENT and the computed tangents (scene/tangents.h) give the same frame on a
// planar quad, for a plain uv mapping (w = +1) and a mirrored one (w = -1): the same image bit
// for bit, since both frames are exactly the axes here. The tilted map makes a wrong sign
// visible.
TEST(GltfNormalMap, ComputedTangentsMatchTheFilesOnAPlanarQuad) {
    const double a = 35.0 * M_PI / 180.0;
    for (bool swapped : {false, true}) {
        QuadOptions o;
        o.texel = encode({std::sin(a) * 0.6, std::sin(a) * 0.8, std::cos(a)});
        o.swappedUvs = swapped;
        QuadOptions computed = o;
        computed.tangents = false;
        const std::string tag = swapped ? "-mirrored" : "";
        Image file = renderQuad("file" + tag, o, 4), ours = renderQuad("computed" + tag, computed, 4);
        EXPECT_EQ(file.rgb, ours.rgb) << (swapped ? "mirrored uvs" : "plain uvs");
    }
}

// computeTangents directly: the frame of each mapping, and no NaN for degenerate uvs.
TEST(GltfNormalMap, ComputedTangentFramesAndDegenerateUvs) {
    Shape s;
    s.type = ShapeType::Mesh;
    s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
    s.indices = {0, 3, 2, 0, 2, 1};
    s.normals.assign(4, glm::vec3(0, 1, 0));
    s.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    computeTangents(s);
    for (const glm::vec4& t : s.tangents) EXPECT_EQ(t, glm::vec4(1, 0, 0, 1));
    s.uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    computeTangents(s);
    for (const glm::vec4& t : s.tangents) EXPECT_EQ(t, glm::vec4(0, 0, 1, -1));
    // All uvs equal: no uv gradient anywhere; a unit tangent perpendicular to N all the same.
    s.uvs.assign(4, glm::vec2(0.25f));
    computeTangents(s);
    for (const glm::vec4& t : s.tangents) {
        EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(glm::vec3(t), glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
        EXPECT_TRUE(t.w == 1.0f || t.w == -1.0f);
    }
}

// The normal AOV reports the bent shading normal (docs/SCENE_FORMAT.md, "Normal maps"), as
// Cycles and Mitsuba write theirs: constant over the quad, so every pixel's mean of its
// samples is that unit vector to float rounding.
TEST(GltfNormalMap, NormalAovIsTheBentNormal) {
    const double a = 30.0 * M_PI / 180.0;
    QuadOptions o;
    o.texel = encode({std::sin(a) * 0.6, std::sin(a) * 0.8, std::cos(a)});
    auto dir = test::freshOutputDir("gltf-normal-map", "aov");
    test::writeFile(dir / "quad.gltf", normalMappedQuad(dir, o));
    json doc = quadScene(4);
    doc["film"]["aovs"] = {"normal"};
    Image image = test::renderScene(test::sceneFromJson(doc, "gltf-normal-map/aov/scene"));
    ASSERT_EQ(image.aovs.size(), 1u);
    const glm::dvec3 n = bentNormal(o.texel, 1.0);
    ASSERT_GT(glm::length(n - glm::dvec3(0, 1, 0)), 0.3);  // far from the geometric normal
    int wrong = 0;
    for (size_t p = 0; p < image.aovs[0].floats.size() / 3; ++p)
        for (int c = 0; c < 3; ++c) wrong += std::fabs(image.aovs[0].floats[3 * p + c] - n[c]) > 1e-5;
    EXPECT_EQ(wrong, 0);
}

// A mirroring to_world (x -> -x) mirrors the tangent frame: T' = L T = -x, and B' = L B = -z
// only with w flipped (cross(N', T') = +z), as host/scene/transform.cpp does. Mirrored
// together with the light and the camera, the quad then shows the original's closed form at
// each mirrored point; with w kept, B' would be +z and the picture the other tilt's.
TEST(GltfNormalMap, MirroringToWorldFlipsTheBitangentSign) {
    const double a = 30.0 * M_PI / 180.0, phi = 60.0 * M_PI / 180.0;
    QuadOptions o;
    o.texel = encode({std::sin(a) * std::cos(phi), std::sin(a) * std::sin(phi), std::cos(a)});
    const glm::dvec3 n = bentNormal(o.texel, 1.0);
    auto dir = test::freshOutputDir("gltf-normal-map", "mirrored");
    test::writeFile(dir / "quad.gltf", normalMappedQuad(dir, o));
    json doc = quadScene(64);
    doc["camera"] = test::topDownCamera(-0.5, 0.5, 0.5);
    doc["shapes"][0]["to_world"] = {{"scale", {-1, 1, 1}}};
    doc["lights"][0]["position"] = {-kLight.x, kLight.y, kLight.z};
    test::expectTopDownMatches(
        doc, {{{"type", "direct"}, {"strategy", "light"}}},
        [&](glm::dvec3 x) {
            return closedForm({-x.x, x.y, x.z}, n);
        },
        "gltf-normal-map/mirrored/scene", 1e-4);
}
