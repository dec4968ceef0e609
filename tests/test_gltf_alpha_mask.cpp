// glTF alphaMode MASK on lavapipe: a quad at height 1 whose base colour texture's alpha is an
// 8 x 8 checkerboard of 0 and 1, over a diffuse floor. Bilinear alpha between texel centres
// crosses the default cutoff 0.5 exactly on the texel edges (along an edge the blend of 0 and 1
// is 1/2 at the midpoint; at a corner (1 - fx)(1 - fy) + fx fy < 1/2 exactly where
// (fx - 1/2)(fy - 1/2) < 0), so the open cells are exactly the checkerboard's alpha-0 squares.
//
// Shadow rays: a directional light travelling along (1, -1, 0) lights floor point (x, z)
// through the quad at (x - 1, z): the floor under x in [1, 2] is lit (albedo/pi x irradiance
// x cos 45) where that cell is open and black where it is not, with pixels 1/64 wide aligned
// to the cells of 1/8, so every pixel is one or the other; the lit fraction must be the open
// fraction, 1/2, within the z bound of its samples. Camera rays: seen from above, the quad's
// open cells show the floor beneath, lit by light that passes beside the quad. BRDF rays:
// under a constant sky, BRDF sampling and light sampling (shadow rays) must estimate the same
// image where the quad's holes let the sky through (a pixel-pair z test).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

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

constexpr int kCells = 8;
constexpr double kAlbedo = 0.5, kIrradiance = 2.0;

// Whether checkerboard cell (i, j) (i along u = x, j along v = z) has alpha 0: the open ones.
bool openCell(int i, int j) { return (i + j) % 2 == 0; }

// An 8 x 8 RGBA PNG: black, alpha 0 on open cells and 255 elsewhere.
void writeCheckerAlpha(const std::filesystem::path& file) {
    std::vector<uint8_t> rgba;
    for (int j = 0; j < kCells; ++j)
        for (int i = 0; i < kCells; ++i) rgba.insert(rgba.end(), {0, 0, 0, uint8_t(openCell(i, j) ? 0 : 255)});
    ASSERT_NE(stbi_write_png(file.string().c_str(), kCells, kCells, 4, rgba.data(), kCells * 4), 0);
}

// The quad x, z in [0, 1] at y = 1, uv (x, z), a black rough pbr material with the checker's
// alpha, alphaMode `mode` (or none), and the texture clamped to its edges.
std::string maskedQuad(const std::filesystem::path& dir, const std::string& mode) {
    writeCheckerAlpha(dir / "checker.png");
    test::GltfBuilder b;
    std::vector<float> uvs = {0, 0, 1, 0, 1, 1, 0, 1};
    json primitive = {{"attributes",
                       {{"POSITION", b.positions({0, 1, 0, 1, 1, 0, 1, 1, 1, 0, 1, 1})},
                        {"TEXCOORD_0", b.addAccessor(uvs.data(), uvs.size() * 4, 5126, 4, "VEC2")}}},
                      {"indices", b.indices({0, 2, 1, 0, 3, 2})},
                      {"material", 0}};
    b.addMeshNode(primitive);
    json material = {{"pbrMetallicRoughness",
                      {{"baseColorFactor", {0, 0, 0, 1}},
                       {"baseColorTexture", {{"index", 0}}},
                       {"metallicFactor", 0},
                       {"roughnessFactor", 1}}}};
    if (!mode.empty()) material["alphaMode"] = mode;
    b.doc["materials"] = {material};
    b.doc["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33071}}};
    b.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    b.doc["images"] = {{{"uri", "checker.png"}}};
    return b.gltf();
}

json floorScene(json camera, json lights, const std::string& strategy, int spp) {
    return {{"camera", camera},
            {"film", {{"width", 64}, {"height", 64}}},
            {"sampler", {{"spp", spp}, {"seed", 11}, {"type", "independent"}}},
            {"integrator", {{"type", "direct"}, {"strategy", strategy}}},
            {"materials", {{"floor", {{"type", "diffuse"}, {"albedo", kAlbedo}}}}},
            {"shapes", json::array({{{"type", "quad"},
                                     {"origin", {-1, 0, 3}},
                                     {"edge_u", {4, 0, 0}},
                                     {"edge_v", {0, 0, -4}},
                                     {"material", "floor"}},
                                    {{"type", "gltf"}, {"file", "quad.gltf"}}})},
            {"lights", lights}};
}

// Where the ray through pixel (px, py)'s point (fx, fy) in [0, 1]^2 of the top-down camera
// centred on (cx, cz) with half-width `half` (render_helpers.h, topDownCamera: image x = world
// x, image y = world z, eye at height 50) crosses height h.
glm::dvec2 crossing(double cx, double cz, double half, int px, int py, double fx, double fy, double h) {
    const double x = cx + half * (2 * (px + fx) / 64 - 1), z = cz + half * (2 * (py + fy) / 64 - 1);
    const double k = (50 - h) / 50;  // the ray from the eye at (cx, 50, cz) to the floor point
    return {cx + (x - cx) * k, cz + (z - cz) * k};
}

// The open state of the quad at plane point q (x, z in [0, 1]), or -1 outside the quad.
int openAt(glm::dvec2 q) {
    if (q.x < 0 || q.x >= 1 || q.y < 0 || q.y >= 1) return -1;
    return openCell(int(q.x * kCells), int(q.y * kCells)) ? 1 : 0;
}

}  // namespace

TEST(GltfAlphaMask, ShadowRaysAndCameraRaysGoThroughTheCutOut) {
    auto dir = test::freshOutputDir("gltf-alpha-mask", "shadow");
    test::writeFile(dir / "quad.gltf", maskedQuad(dir, "MASK"));
    const json sun = json::array({{{"type", "directional"}, {"direction", {1, -1, 0}}, {"irradiance", kIrradiance}}});
    const double lit = kAlbedo / M_PI * kIrradiance * std::sqrt(0.5);
    const int spp = 16;

    // The floor under x in [1, 2], z in [0, 1], lit through the quad at (x - 1, z).
    Image shadow = test::renderScene(test::sceneFromJson(
        floorScene(test::topDownCamera(1.5, 0.5, 0.5), sun, "mis", spp), "gltf-alpha-mask/shadow/shadow"));
    writeExr(test::outputPath("gltf-alpha-mask/shadow/shadow.exr"), shadow);
    // A pixel's footprint, 2% wider on each side: the samples on a cell's edge (a pixel's
    // edge) may go either way by a rounding, so pixels beside an edge are only counted.
    auto uniformState = [](double cx, double cz, int px, int py, double h, glm::dvec2 shift) {
        const int state = openAt(crossing(cx, cz, 0.5, px, py, 0.5, 0.5, h) - shift);
        for (double fy : {-0.02, 1.02})
            for (double fx : {-0.02, 1.02})
                if (openAt(crossing(cx, cz, 0.5, px, py, fx, fy, h) - shift) != state) return -2;
        return state;
    };
    double sum = 0;
    int wrong = 0, checked = 0;
    for (int py = 0; py < 64; ++py)
        for (int px = 0; px < 64; ++px) {
            const double got = shadow.pixel(uint32_t(px), uint32_t(py))[0];
            sum += got;
            const int state = uniformState(1.5, 0.5, px, py, 0.0, glm::dvec2(1, 0));
            if (state < 0) continue;
            const bool open = state == 1;
            ++checked;
            if (std::fabs(got - (open ? lit : 0.0)) > 1e-3 * lit && wrong++ < 8)
                ADD_FAILURE() << "shadow pixel (" << px << ", " << py << "): " << got << ", expected "
                              << (open ? lit : 0.0);
        }
    // The lit fraction against the open fraction 1/2: each sample is lit or not, so its
    // standard deviation is at most 1/2 over sqrt(samples).
    const double fraction = sum / (64.0 * 64.0 * lit);
    EXPECT_LT(std::fabs(fraction - 0.5), test::zScore(1e-4, 1) * 0.5 / std::sqrt(64.0 * 64.0 * spp))
        << "lit fraction " << fraction;
    EXPECT_GT(checked, 64 * 64 / 2);

    // Seen from above, the quad's open cells show the floor, lit beside the quad; its black,
    // rough opaque cells reflect a little of the light (the specular F0 of 0.04).
    Image view = test::renderScene(test::sceneFromJson(floorScene(test::topDownCamera(0.5, 0.5, 0.5), sun, "mis", spp),
                                                       "gltf-alpha-mask/shadow/view"));
    writeExr(test::outputPath("gltf-alpha-mask/shadow/view.exr"), view);
    int open = 0, closed = 0;
    wrong = 0;
    for (int py = 0; py < 64; ++py)
        for (int px = 0; px < 64; ++px) {
            // Only pixels whose footprint on the quad is in one cell, and whose floor's light
            // passes wholly beside the quad (not along its edge).
            const int state = uniformState(0.5, 0.5, px, py, 1.0, glm::dvec2(0));
            if (state < 0 || uniformState(0.5, 0.5, px, py, 0.0, glm::dvec2(1, 0)) != -1) continue;
            const double got = view.pixel(uint32_t(px), uint32_t(py))[0];
            const bool ok = state == 1 ? std::fabs(got - lit) <= 1e-3 * lit : got < 0.5 * lit;
            (state == 1 ? open : closed)++;
            if (!ok && wrong++ < 8)
                ADD_FAILURE() << "view pixel (" << px << ", " << py << ") " << (state == 1 ? "open" : "closed") << ": "
                              << got << " (floor lit: " << lit << ")";
        }
    EXPECT_GT(open, 1000);
    EXPECT_GT(closed, 1000);
}

TEST(GltfAlphaMask, BrdfRaysGoThroughTheCutOutAsShadowRaysDo) {
    auto dir = test::freshOutputDir("gltf-alpha-mask", "sky");
    test::writeFile(dir / "quad.gltf", maskedQuad(dir, "MASK"));
    const json sky = json::array({{{"type", "environment"}, {"radiance", 1}}});
    std::vector<Image> images;
    for (const std::string strategy : {"light", "bsdf"})
        images.push_back(test::renderScene(test::sceneFromJson(
            floorScene(test::topDownCamera(0.5, 0.5, 1.5), sky, strategy, 32), "gltf-alpha-mask/sky/" + strategy)));
    writeExr(test::outputPath("gltf-alpha-mask/sky/light.exr"), images[0]);
    writeExr(test::outputPath("gltf-alpha-mask/sky/bsdf.exr"), images[1]);
    // Each pixel's two estimates have the same mean: D = light - bsdf has mean 0 at every
    // pixel, so sum D / sqrt(sum D^2) is a z statistic (alpha 1e-4 over the 3 channels).
    const double z = test::zScore(1e-4, 3);
    for (int c = 0; c < 3; ++c) {
        double sum = 0, sum2 = 0;
        for (size_t k = size_t(c); k < images[0].rgb.size(); k += 3) {
            const double d = double(images[0].rgb[k]) - images[1].rgb[k];
            sum += d;
            sum2 += d * d;
        }
        ASSERT_GT(sum2, 0.0);
        EXPECT_LT(std::fabs(sum) / std::sqrt(sum2), z) << "channel " << c << ": light - bsdf sums to " << sum;
    }
}

TEST(GltfAlphaMask, ModesCutoffsAndConstantAlpha) {
    auto dir = test::freshOutputDir("gltf-alpha-mask", "modes");
    auto load = [&](const json& doc) { return loadScene(test::writeFile(dir / "quad.gltf", doc.dump())); };
    auto bits = [&](const Scene& s) { return makeKernelOptions(s, buildSceneArrays(s)).textures; };
    const json base = json::parse(maskedQuad(dir, ""));
    auto hasNote = [](const Scene& s, const std::string& part) {
        for (const std::string& n : s.notes)
            if (n.find(part) != std::string::npos) return true;
        return false;
    };
    // OPAQUE (the default) has no alpha test; MASK and BLEND do (BLEND with a note).
    EXPECT_EQ(bits(load(base)) & TEXTURES_ALPHA_MASK, 0u);
    json mask = base;
    mask["materials"][0]["alphaMode"] = "MASK";
    EXPECT_NE(bits(load(mask)) & TEXTURES_ALPHA_MASK, 0u);
    json blend = base;
    blend["materials"][0]["alphaMode"] = "BLEND";
    Scene blended = load(blend);
    EXPECT_NE(bits(blended) & TEXTURES_ALPHA_MASK, 0u);
    EXPECT_TRUE(hasNote(blended, "with alphaMode BLEND are rendered as MASK with alphaCutoff 0.5"));
    // A constant alpha: opaque at or above the cutoff, no primitive at all below it.
    json constant = mask;
    constant["materials"][0]["pbrMetallicRoughness"].erase("baseColorTexture");
    constant["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {0, 0, 0, 0.5};
    Scene opaque = load(constant);
    EXPECT_EQ(bits(opaque), 0u);
    EXPECT_EQ(opaque.shapes.size(), 1u);
    constant["materials"][0]["alphaCutoff"] = 0.75;
    Scene gone = load(constant);
    EXPECT_TRUE(gone.shapes.empty());
    EXPECT_TRUE(hasNote(gone, "skipped 1 primitives whose material is cut out everywhere"));
    // Errors name their path.
    json bad = base;
    bad["materials"][0]["alphaMode"] = "CUTOUT";
    auto file = test::writeFile(dir / "bad.gltf", bad.dump());
    EXPECT_EQ(test::loadError(file),
              file.string() + ": materials[0].alphaMode: expected \"OPAQUE\", \"MASK\" or \"BLEND\"");
    bad = mask;
    bad["materials"][0]["alphaCutoff"] = -1;
    file = test::writeFile(dir / "bad.gltf", bad.dump());
    EXPECT_EQ(test::loadError(file), file.string() + ": materials[0].alphaCutoff: must be a finite number >= 0");
}
