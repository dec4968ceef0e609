// glTF emissive textures (emissiveFactor x emissiveTexture as mesh-light radiance), rendered
// on lavapipe against a closed form, and the ClearCoatTest labels of Debian's assimp-testmodels.
//
// Closed form: a two-sided emissive quad at height 1 over a diffuse floor, seen from straight
// above, with u = x + 1/2 across the quad and a 2 x 1 texture of texels 1 and 0 (clamped to
// the edge). Bilinear filtering makes t(u) = 1 for u < 1/4, 0 for u > 3/4 and linear between,
// so t(u) + t(1 - u) = 1 everywhere. The scene and the camera are symmetric under x -> -x, so
// for any pixel p and its mirror image p', E[T(p)] + E[T(p')] = 2 E[C(p)], where C is the same
// scene with a constant emission of the texture's mean, 1/2: every point of the emitter and its
// mirror image together emit what two points of the constant emitter do, towards any point of
// the floor (and towards the camera). D(p) = (T(p) + T(p')) / 2 - C(p) has mean 0 for every
// pixel pair and independent samples, so sum D / sqrt(sum D^2) is a z statistic (alpha 1e-4,
// two-sided, Bonferroni over strategies and channels). Light samples carry the texture in their
// radiance (lights/mesh.glsl), BRDF-sampled and camera rays read it at their hit
// (integrators/direct.comp): each strategy, and MIS between them, must agree.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gltf_builder.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "render/kernel_options.h"
#include "render/scene_arrays.h"
#include "render_helpers.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr int kSize = 48;
constexpr int kSpp = 64;

// The emitter: a quad over x, z in [-1/2, 1/2] at y = 1, uv u = x + 1/2, v = z + 1/2, two-sided,
// emissiveFactor `factor`, with the 2 x 1 texture (white, black) or none.
std::string emitterModel(const std::filesystem::path& dir, glm::dvec3 factor, bool textured) {
    test::GltfBuilder b;
    std::vector<float> uvs = {0, 0, 1, 0, 1, 1, 0, 1};
    json primitive = {{"attributes",
                       {{"POSITION", b.positions({-0.5f, 1, -0.5f, 0.5f, 1, -0.5f, 0.5f, 1, 0.5f, -0.5f, 1, 0.5f})},
                        {"TEXCOORD_0", b.addAccessor(uvs.data(), uvs.size() * 4, 5126, 4, "VEC2")}}},
                      {"indices", b.indices({0, 1, 2, 0, 2, 3})},
                      {"material", 0}};
    b.addMeshNode(primitive);
    json material = {{"emissiveFactor", {factor.x, factor.y, factor.z}},
                     {"doubleSided", true},
                     {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}}};
    if (textured) {
        material["emissiveTexture"] = {{"index", 0}};
        b.doc["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33071}}};
        b.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
        b.doc["images"] = {{{"uri", "split.png"}}};
        writePngRgb8(dir / "split.png", 2, 1, {255, 255, 255, 0, 0, 0});
    }
    b.doc["materials"] = {material};
    return b.gltf();
}

Image renderEmitter(const std::string& model, const std::string& strategy, const std::string& name,
                    Scene* loadedOut = nullptr) {
    json scene = {{"camera", test::topDownCamera(0, 0, 1.5)},
                  {"film", {{"width", kSize}, {"height", kSize}}},
                  {"sampler", {{"spp", kSpp}, {"seed", 7}, {"type", "independent"}}},
                  {"integrator", {{"type", "direct"}, {"strategy", strategy}}},
                  {"materials", {{"floor", {{"type", "diffuse"}, {"albedo", 0.8}}}}},
                  {"shapes", json::array({{{"type", "quad"},
                                           {"origin", {-3, 0, 3}},
                                           {"edge_u", {6, 0, 0}},
                                           {"edge_v", {0, 0, -6}},
                                           {"material", "floor"}},
                                          {{"type", "gltf"}, {"file", model}}})}};
    Scene loaded = test::sceneFromJson(scene, "gltf-emissive-texture/" + name);
    if (loadedOut) *loadedOut = loaded;
    Image image = test::renderScene(loaded);
    writeExr(test::outputPath("gltf-emissive-texture/" + name + ".exr"), image);
    return image;
}

}  // namespace

TEST(GltfEmissiveTexture, TexturedQuadLightMatchesItsMeanWhereTheSceneIsSymmetric) {
    auto dir = test::freshOutputDir("gltf-emissive-texture", "split");
    test::writeFile(dir / "textured.gltf", emitterModel(dir, glm::dvec3(1.0), true));
    test::writeFile(dir / "constant.gltf", emitterModel(dir, glm::dvec3(0.5), false));
    Scene texturedScene;
    const std::vector<std::string> strategies = {"light", "bsdf", "mis"};
    std::vector<Image> textured;
    for (const std::string& s : strategies)
        textured.push_back(renderEmitter("textured.gltf", s, "split/textured-" + s, &texturedScene));
    Image constant = renderEmitter("constant.gltf", "mis", "split/constant");

    // The texture is on the GPU only for the textured model's emitter.
    EXPECT_EQ(texturedScene.materials.back().textures.size(), 1u);
    SceneArrays arrays = buildSceneArrays(texturedScene);
    EXPECT_NE(makeKernelOptions(texturedScene, arrays).textures & TEXTURES_EMISSION, 0u);

    const double z = test::zScore(1e-4, int(strategies.size()) * 3);
    for (size_t k = 0; k < strategies.size(); ++k) {
        const Image& t = textured[k];
        for (int c = 0; c < 3; ++c) {
            double sum = 0, sum2 = 0, left = 0, right = 0, sideSum2 = 0;
            for (uint32_t y = 0; y < t.height; ++y)
                for (uint32_t x = 0; x < t.width / 2; ++x) {
                    const uint32_t mirror = t.width - 1 - x;
                    const double a = t.pixel(x, y)[c], b = t.pixel(mirror, y)[c];
                    const double d = 0.5 * (a + b) - 0.5 * (constant.pixel(x, y)[c] + constant.pixel(mirror, y)[c]);
                    sum += d;
                    sum2 += d * d;
                    left += a;
                    right += b;
                    sideSum2 += (a - b) * (a - b);
                }
            ASSERT_GT(sum2, 0.0);
            EXPECT_LT(std::fabs(sum) / std::sqrt(sum2), z)
                << strategies[k] << " channel " << c << ": textured vs constant-mean pixel pairs differ by " << sum;
            // The white texel is at u < 1/2, x < 0 (the image's left): the floor under it is
            // brighter there, far beyond the noise (a texture read mirrored, or ignored,
            // would not be).
            EXPECT_GT((left - right) / std::sqrt(sideSum2), 10.0) << strategies[k] << " channel " << c;
        }
    }
}

// A shape's own emission replaces the file's emissive texture, and a model with no
// emissive texture keeps the kernel without its lookups.
TEST(GltfEmissiveTexture, OnlyTexturedEmittersCompileTheLookup) {
    auto dir = test::freshOutputDir("gltf-emissive-texture", "bits");
    test::writeFile(dir / "textured.gltf", emitterModel(dir, glm::dvec3(1.0), true));
    test::writeFile(dir / "constant.gltf", emitterModel(dir, glm::dvec3(0.5), false));
    auto bits = [&](const json& shape) {
        json scene = {{"camera", test::topDownCamera(0, 0, 1.5)},
                      {"shapes", json::array({shape})},
                      {"lights", json::array({{{"type", "environment"}, {"radiance", 1}}})}};
        Scene loaded = test::sceneFromJson(scene, "gltf-emissive-texture/bits/scene");
        return makeKernelOptions(loaded, buildSceneArrays(loaded)).textures;
    };
    EXPECT_EQ(bits({{"type", "gltf"}, {"file", "textured.gltf"}}), TEXTURES_ON | TEXTURES_EMISSION);
    EXPECT_EQ(bits({{"type", "gltf"}, {"file", "constant.gltf"}}), 0u);
    EXPECT_EQ(bits({{"type", "gltf"}, {"file", "textured.gltf"}, {"emission", {1, 1, 1}}}), 0u);
}

// ClearCoatTest's labels are one emissive material (factor 1) whose texture holds the
// lettering, black on white: without the texture they were white bars. Rendered with and
// without the texture, of the label pixels that are white without it, most stay bright with
// it (the background) and many are greyed by the letters (a text line covers about a third
// of its pixels' area, the lines fill most of the label: at least a tenth of the pixels lose
// a quarter of their brightness).
TEST(GltfEmissiveTexture, ClearCoatLabelsShowTheirLettering) {
    const std::filesystem::path src = "/usr/share/assimp/models/glTF2/ClearCoat-glTF";
    ASSERT_TRUE(std::filesystem::exists(src / "ClearCoatTest.gltf")) << "install assimp-testmodels (tools/setup)";
    auto dir = test::freshOutputDir("gltf-emissive-texture", "clearcoat");
    for (const auto& entry : std::filesystem::directory_iterator(src))
        std::filesystem::copy_file(entry.path(), dir / entry.path().filename(),
                                   std::filesystem::copy_options::overwrite_existing);
    json model = json::parse(std::ifstream(src / "ClearCoatTest.gltf"));
    for (json& m : model["materials"]) m.erase("emissiveTexture");
    test::writeFile(dir / "bars.gltf", model.dump());
    const std::vector<Override> film = {{"film.width", "256"}, {"film.height", "256"}, {"sampler.spp", "8"}};
    Image labels = test::renderScene(loadScene(dir / "ClearCoatTest.gltf", film));
    Image bars = test::renderScene(loadScene(dir / "bars.gltf", film));
    writeExr(test::outputPath("gltf-emissive-texture/clearcoat/labels.exr"), labels);
    writeExr(test::outputPath("gltf-emissive-texture/clearcoat/bars.exr"), bars);
    size_t white = 0, dark = 0, bright = 0;
    for (uint32_t y = 0; y < bars.height; ++y)
        for (uint32_t x = 0; x < bars.width; ++x) {
            const float* b = bars.pixel(x, y);
            if (!(b[0] > 0.95f && b[1] > 0.95f && b[2] > 0.95f)) continue;  // not on a white bar
            ++white;
            const float* l = labels.pixel(x, y);
            const float luminance = (l[0] + l[1] + l[2]) / 3;
            dark += luminance < 0.75f;
            bright += luminance > 0.9f;
        }
    std::printf("ClearCoatTest: %zu white-bar pixels, %zu greyed and %zu bright with the texture\n", white, dark,
                bright);
    EXPECT_GT(white, 200u);
    EXPECT_GT(bright, white / 2);
    EXPECT_GT(dark, white / 10);
}
