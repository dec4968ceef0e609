// The Khronos TextureTransformTest sample (Debian's assimp-testmodels) rendered head-on:
// each of its six quads shows its texture where KHR_texture_transform puts it. The checks
// are a few pixels per quad whose colour the right transform, the untransformed lookup and
// the opposite rotation (the "Error" marker's reading) all predict differently; the closed
// form of the transform itself is checked texel by texel in test_textures.cpp.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "image/image.h"
#include "image/image_file.h"
#include "render_helpers.h"
#include "scene/load.h"

using namespace penumbra;
using nlohmann::json;

namespace {

const std::filesystem::path kModelDir = "/usr/share/assimp/models/glTF2/textureTransform";

// The extension's uv map (see host/scene/gltf_texture_transform.cpp for the rotation's sense).
glm::dvec2 transformUv(const json& ext, glm::dvec2 uv, double rotationSign = 1) {
    glm::dvec2 offset(0), scale(1);
    if (ext.contains("offset")) offset = {ext["offset"][0].get<double>(), ext["offset"][1].get<double>()};
    if (ext.contains("scale")) scale = {ext["scale"][0].get<double>(), ext["scale"][1].get<double>()};
    const double r = rotationSign * ext.value("rotation", 0.0), c = std::cos(r), s = std::sin(r);
    return {c * scale.x * uv.x + s * scale.y * uv.y + offset.x, -s * scale.x * uv.x + c * scale.y * uv.y + offset.y};
}

// The texel colour around `uv` (clamp to edge, as the model's sampler says) if the 7 x 7
// texels around it are one colour (within 0.02): bilinear filtering and a pixel's footprint
// (under two texels at this film size) then see nothing else.
std::optional<glm::dvec3> uniformColour(const ImageFile& image, glm::dvec2 uv) {
    const int cx = int(std::floor(uv.x * image.width)), cy = int(std::floor(uv.y * image.height));
    glm::dvec3 lo(1e9), hi(-1e9);
    for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx) {
            const float* t = image.texel(uint32_t(std::clamp(cx + dx, 0, int(image.width) - 1)),
                                         uint32_t(std::clamp(cy + dy, 0, int(image.height) - 1)));
            glm::dvec3 c(t[0], t[1], t[2]);
            lo = glm::min(lo, c);
            hi = glm::max(hi, c);
        }
    if (std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) > 0.02) return std::nullopt;
    return lo;
}

double maxDifference(glm::dvec3 a, glm::dvec3 b) {
    glm::dvec3 d = glm::abs(a - b);
    return std::max({d.x, d.y, d.z});
}

}  // namespace

TEST(GltfTextureTransform, TextureTransformTestSampleShowsEveryQuadTransformed) {
    ASSERT_TRUE(std::filesystem::exists(kModelDir / "TextureTransformTest.gltf"))
        << "install assimp-testmodels (tools/setup)";
    auto dir = test::freshOutputDir("gltf-texture-transform", "sample");
    for (const auto& entry : std::filesystem::directory_iterator(kModelDir))
        std::filesystem::copy_file(entry.path(), dir / entry.path().filename(),
                                   std::filesystem::copy_options::overwrite_existing);
    json model = json::parse(std::ifstream(kModelDir / "TextureTransformTest.gltf"));

    // Head-on, 100 pixels per unit: world (x, y, 0) is at pixel (165 + 100 x, 110 - 100 y).
    // The ao integrator returns the base colour of a plane that nothing occludes within
    // max_distance exactly (the file's base colour factors are 1): the pixels read the
    // texture itself. The markers float 0.01 in front of the quads: within 0.005 nothing does.
    const int width = 330, height = 220;
    json scene = {{"camera",
                   {{"eye", {0, 0, 5}},
                    {"target", {0, 0, 0}},
                    {"up", {0, 1, 0}},
                    {"fov_y", 2 * std::atan(1.1 / 5) * 180 / M_PI}}},
                  {"film", {{"width", width}, {"height", height}}},
                  {"sampler", {{"spp", 16}, {"seed", 1}}},
                  {"integrator", {{"type", "ao"}, {"max_distance", 0.005}}},
                  {"shapes", json::array({{{"type", "gltf"}, {"file", "TextureTransformTest.gltf"}}})},
                  {"lights", json::array({{{"type", "environment"}, {"radiance", 1}}})}};
    Scene loaded = test::sceneFromJson(scene, "gltf-texture-transform/sample/scene");
    Image image = test::renderScene(loaded);
    writeExr(test::outputPath("gltf-texture-transform/sample/render.exr"), image);
    writePng(test::outputPath("gltf-texture-transform/sample/render.png"), image);

    // Marker quads (unit quads scaled by their node, children of the transformed quads'
    // nodes, drawn 0.01 in front): the probes keep 0.02 (two pixels) off them, which they hide.
    struct Marker {
        glm::dvec2 centre;
        double half;
    };
    std::vector<Marker> markers;
    for (const json& node : model["nodes"])
        for (const json& child : node.value("children", json::array())) {
            const json& c = model["nodes"][child.get<size_t>()];
            markers.push_back({{node["translation"][0].get<double>() + c["translation"][0].get<double>(),
                                node["translation"][1].get<double>() + c["translation"][1].get<double>()},
                               0.5 * c["scale"][0].get<double>()});
        }

    int quads = 0;
    for (const json& node : model["nodes"]) {
        const int mesh = node.value("mesh", -1);
        if (mesh < 0 || mesh > 5) continue;  // meshes 6-8 are the markers
        ++quads;
        const json& material = model["materials"][model["meshes"][mesh]["primitives"][0]["material"].get<size_t>()];
        const json& info = material["pbrMetallicRoughness"]["baseColorTexture"];
        const json& ext = info["extensions"]["KHR_texture_transform"];
        const std::string file =
            model["images"][model["textures"][info["index"].get<size_t>()]["source"].get<size_t>()]["uri"]
                .get<std::string>();
        ImageFile texture = readImageFile(kModelDir / file, ColorDecode::Srgb);
        // The top row's quads have uvs over [0, 0.5]^2, the bottom row's over [0, 1]^2;
        // uv (0, 0) is the quad's top-left corner, u to the right, v down.
        const double uvMax = mesh < 3 ? 0.5 : 1.0;
        const glm::dvec2 centre(node["translation"][0].get<double>(), node["translation"][1].get<double>());
        int probes = 0;
        for (int j = 1; j < 80 && probes < 8; ++j)
            for (int i = 1; i < 80 && probes < 8; ++i) {
                const glm::dvec2 a(i / 80.0, j / 80.0);
                const glm::dvec2 world = centre + glm::dvec2(-0.5 + a.x, 0.5 - a.y);
                bool nearMarker = false;
                for (const Marker& m : markers) {
                    const glm::dvec2 d = glm::abs(world - m.centre);
                    nearMarker |= std::max(d.x, d.y) < m.half + 0.02;
                }
                if (nearMarker) continue;
                const glm::dvec2 uv = uvMax * a;
                auto right = uniformColour(texture, transformUv(ext, uv));
                auto untransformed = uniformColour(texture, uv);
                auto opposite = uniformColour(texture, transformUv(ext, uv, -1));
                if (!right || !untransformed || !opposite) continue;
                if (maxDifference(*right, *untransformed) < 0.3) continue;
                if (ext.contains("rotation") && maxDifference(*right, *opposite) < 0.3) continue;
                ++probes;
                const float* got = image.pixel(uint32_t(165 + 100 * world.x), uint32_t(110 - 100 * world.y));
                EXPECT_LT(maxDifference(glm::dvec3(got[0], got[1], got[2]), *right), 0.03)
                    << material["name"] << " at quad (" << a.x << ", " << a.y << "): got (" << got[0] << ", " << got[1]
                    << ", " << got[2] << "), expected (" << right->x << ", " << right->y << ", " << right->z
                    << "); untransformed (" << untransformed->x << ", " << untransformed->y << ", " << untransformed->z
                    << ")";
            }
        // Every quad's transform changes what some of its pixels show.
        EXPECT_GE(probes, 3) << material["name"];
    }
    EXPECT_EQ(quads, 6);
}
