// Material textures rendered on lavapipe against a CPU evaluation of SCENE_FORMAT.md
// "Textures (v2)": bilinear between texel centres, repeat wrapping, row 0 at v = 0, quad
// (s, t), interpolated mesh `uvs` and sphere coordinates; sRGB PNG colours decoded before
// filtering. Every scene is a diffuse convex surface under a constant environment of
// radiance 1, so a pixel sample sees exactly the albedo at its point (cosine-weighted light
// and BRDF samples both estimate albedo x 1 with no variance, and a convex surface does not
// shadow itself): the only noise is where the samples land in the pixel, whose variance the
// CPU evaluation measures. Independent samples, so that the normal bound applies.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/packing.hpp>

#include "gltf_builder.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "image/image_file.h"
#include "render/kernel_options.h"
#include "render/scene_arrays.h"
#include "render_helpers.h"
#include "scene/load.h"
#include "scene_test_util.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr int kSize = 40;
constexpr int kSpp = 64;
constexpr double kAlpha = 1e-4;
// Float (GPU) against double (CPU) hit points and uvs: a few 1e-6 in uv, times the
// steepest texel step per uv (0.5 x 12 texels) stays far below this.
constexpr double kRounding = 2e-4;

// A texture on the CPU: RGBA per texel, row 0 at the top.
struct CpuTexture {
    int width = 0, height = 0;
    std::vector<float> rgba;
    double at(int x, int y, int c) const { return rgba[(size_t(y) * width + x) * 4 + c]; }

    // SCENE_FORMAT.md: bilinear between texel centres ((i + 0.5) / W, (j + 0.5) / H), repeat;
    // glTF samplers may clamp to the edge or mirror instead (along u: `wrapU`).
    double bilinear(double u, double v, int c, TextureWrap wrapU = TextureWrap::Repeat) const {
        double px = 0, py = (v - std::floor(v)) * height - 0.5;
        if (wrapU == TextureWrap::Repeat) px = (u - std::floor(u)) * width - 0.5;
        // Mirror: copies alternate flipped, u and 2 - u read the same point.
        else if (wrapU == TextureWrap::Mirror) px = (1 - std::fabs(u - 2 * std::floor(u / 2) - 1)) * width - 0.5;
        else px = u * width - 0.5;
        double fx = px - std::floor(px), fy = py - std::floor(py);
        int x0 = int(std::floor(px)), y0 = int(std::floor(py));
        auto repeat = [](int i, int n) { return ((i % n) + n) % n; };
        auto edge = [](int i, int n) { return std::clamp(i, 0, n - 1); };
        auto wrapX = [&](int i) { return wrapU == TextureWrap::Repeat ? repeat(i, width) : edge(i, width); };
        int xa = wrapX(x0), xb = wrapX(x0 + 1), ya = repeat(y0, height), yb = repeat(y0 + 1, height);
        return (1 - fy) * ((1 - fx) * at(xa, ya, c) + fx * at(xb, ya, c)) +
               fy * ((1 - fx) * at(xa, yb, c) + fx * at(xb, yb, c));
    }
};

// 4 x 3 (not square, so that a transposed read shows), every value a multiple of 1/8 and
// exact in half precision: R a checkerboard, G growing to the right, B growing downwards.
CpuTexture checkerboard() {
    CpuTexture t;
    t.width = 4;
    t.height = 3;
    for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x)
            t.rgba.insert(t.rgba.end(),
                          {(x + y) % 2 ? 0.75f : 0.25f, 0.125f + 0.25f * float(x), 0.875f - 0.25f * float(y), 1.0f});
    return t;
}

std::filesystem::path writeExrTexture(const CpuTexture& t, const std::filesystem::path& file) {
    Image image;
    image.width = uint32_t(t.width);
    image.height = uint32_t(t.height);
    for (size_t i = 0; i < t.rgba.size(); i += 4)
        image.rgb.insert(image.rgb.end(), {t.rgba[i], t.rgba[i + 1], t.rgba[i + 2]});
    writeExr(file, image);
    return file;
}

// What one camera ray sees: the value of channel c at its first hit, or nothing on a miss.
using RayValue = std::function<std::optional<double>(glm::dvec3 origin, glm::dvec3 dir, int c)>;

struct Expected {
    std::vector<double> mean, variance;  // per pixel and channel
    std::vector<bool> mixed;             // the pixel holds a silhouette (hits and misses)
};

// Pixel means over a sub x sub grid of the pixel, with the renderer's camera (cameraRay in
// integrators/kernel_common.glsl); a miss sees the environment, radiance 1.
Expected expectedImage(const Scene& scene, const RayValue& value, int sub = 12) {
    SceneArrays arrays = buildSceneArrays(scene);
    gpu::RenderParams p = makeRenderParams(scene, arrays);
    const int w = int(scene.film.width), h = int(scene.film.height);
    Expected e;
    e.mean.assign(size_t(w) * h * 3, 0.0);
    e.variance.assign(e.mean.size(), 0.0);
    e.mixed.assign(size_t(w) * h, false);
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px)
            for (int c = 0; c < 3; ++c) {
                double sum = 0, sum2 = 0;
                int hits = 0;
                for (int j = 0; j < sub; ++j)
                    for (int i = 0; i < sub; ++i) {
                        double fx = (px + (i + 0.5) / sub) / w, fy = (py + (j + 0.5) / sub) / h;
                        glm::dvec3 dir = glm::normalize(
                            glm::dvec3(p.forward) + ((2 * fx - 1) * p.aspect * p.tanHalfFovY) * glm::dvec3(p.right) +
                            ((1 - 2 * fy) * p.tanHalfFovY) * glm::dvec3(p.up));
                        std::optional<double> v = value(glm::dvec3(p.eye), dir, c);
                        hits += v.has_value();
                        double x = v.value_or(1.0);
                        sum += x;
                        sum2 += x * x;
                    }
                double n = double(sub) * sub, mean = sum / n;
                size_t k = (size_t(py) * w + px) * 3 + c;
                e.mean[k] = mean;
                e.variance[k] = std::max(0.0, sum2 / n - mean * mean);
                if (hits != 0 && hits != sub * sub) e.mixed[size_t(py) * w + px] = true;
            }
    return e;
}

// Every pixel that is not a silhouette within z sigma of the jitter noise (Bonferroni over
// all pixels and channels) plus the rounding allowance. Returns the number of failures.
int compare(const Image& image, const Expected& e, const std::string& name) {
    const double z = test::zScore(kAlpha, int(image.width * image.height * 3));
    int failures = 0;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            if (e.mixed[size_t(y) * image.width + x]) continue;
            for (int c = 0; c < 3; ++c) {
                size_t k = (size_t(y) * image.width + x) * 3 + c;
                double tolerance = z * std::sqrt(e.variance[k] / kSpp) + kRounding;
                double got = image.pixel(x, y)[c];
                if (!(std::fabs(got - e.mean[k]) <= tolerance)) {
                    if (failures < 10)
                        ADD_FAILURE() << name << ": pixel (" << x << ", " << y << ") channel " << c << ": " << got
                                      << ", expected " << e.mean[k] << " +- " << tolerance;
                    ++failures;
                }
            }
        }
    if (failures) writeExr(test::outputPath("textures-" + name + ".exr"), image);
    return failures;
}

json sceneWith(json camera, json material, json shape) {
    shape["material"] = "m";
    return {{"camera", camera},
            {"film", {{"width", kSize}, {"height", kSize}}},
            {"sampler", {{"spp", kSpp}, {"seed", 3}, {"type", "independent"}}},
            {"materials", {{"m", material}}},
            {"shapes", json::array({shape})},
            {"lights", json::array({{{"type", "environment"}, {"radiance", 1}}})}};
}

// The plane y = 0 point a ray from above hits (the top-down camera's rays all go down).
glm::dvec3 planeHit(glm::dvec3 o, glm::dvec3 d) { return o + d * (-o.y / d.y); }

// The checkerboard (written to dir/checker.exr) scaled by kCheckerScale on the quad
// [-1, 1]^2 of the plane y = 0, s along +x, t along +z; the camera sees [-0.95, 0.95]^2 of
// it, so the border pixels blend across the repeat seam.
const glm::dvec3 kCheckerScale(1, 0.8, 1);

json checkerQuadScene(const CpuTexture& tex, const std::filesystem::path& dir) {
    writeExrTexture(tex, dir / "checker.exr");
    json quad = {{"type", "quad"}, {"origin", {-1, 0, -1}}, {"edge_u", {2, 0, 0}}, {"edge_v", {0, 0, 2}}};
    return sceneWith(
        test::topDownCamera(0, 0, 0.95),
        {{"type", "diffuse"},
         {"albedo", {{"texture", "checker.exr"}, {"scale", {kCheckerScale.x, kCheckerScale.y, kCheckerScale.z}}}}},
        quad);
}

// What the contract's bilinear lookup (row 0 at v = 0) gives along each camera ray.
Expected expectedChecker(const Scene& loaded, const CpuTexture& tex) {
    return expectedImage(loaded, [&](glm::dvec3 o, glm::dvec3 d, int c) -> std::optional<double> {
        glm::dvec3 x = planeHit(o, d);
        return kCheckerScale[c] * tex.bilinear((x.x + 1) / 2, (x.z + 1) / 2, c);
    });
}

}  // namespace

TEST(Textures, QuadCheckerboardIsBilinearWithRowZeroAtVZero) {
    auto dir = test::freshOutputDir("textures", "quad");
    CpuTexture tex = checkerboard();
    Scene loaded = test::sceneFromJson(checkerQuadScene(tex, dir), "textures/quad/scene");
    Image image = test::renderScene(loaded);
    Expected e = expectedChecker(loaded, tex);
    EXPECT_EQ(compare(image, e, "quad"), 0);

    // The same lookups must fail against a texture read upside down (row 0 at v = 1): the
    // comparison can tell the contract's orientation from its mirror image.
    Expected flipped = expectedImage(loaded, [&](glm::dvec3 o, glm::dvec3 d, int c) -> std::optional<double> {
        glm::dvec3 x = planeHit(o, d);
        return kCheckerScale[c] * tex.bilinear((x.x + 1) / 2, 1.0 - (x.z + 1) / 2, c);
    });
    int mismatches = 0;
    for (size_t k = 0; k < flipped.mean.size(); ++k) mismatches += std::fabs(image.rgb[k] - flipped.mean[k]) > 0.05;
    EXPECT_GT(mismatches, kSize * kSize / 4);
}

// The albedo AOV (SCENE_FORMAT.md "AOVs (v3)") of a textured quad seen head-on is the
// texture, filtered as the contract says and averaged over the pixel's samples: the same
// expected image as the radiance above (which, under the unit environment, is the albedo).
TEST(Textures, AlbedoLayerOfATexturedQuadIsTheTexture) {
    auto dir = test::freshOutputDir("textures", "albedo-aov");
    CpuTexture tex = checkerboard();
    json scene = checkerQuadScene(tex, dir);
    scene["film"]["aovs"] = {"albedo"};
    Scene loaded = test::sceneFromJson(scene, "textures/albedo-aov/scene");
    Image albedo = test::renderScene(loaded);
    ASSERT_EQ(albedo.aovs.size(), 1u);
    albedo.rgb = albedo.aovs[0].floats;  // compared as an image
    Expected e = expectedChecker(loaded, tex);
    EXPECT_EQ(compare(albedo, e, "albedo-aov"), 0);
}

TEST(Textures, MeshUvsInterpolateAndRepeat) {
    auto dir = test::freshOutputDir("textures", "mesh");
    CpuTexture tex = checkerboard();
    writeExrTexture(tex, dir / "checker.exr");
    // Two triangles over [-1, 1]^2 whose uvs run from -1 to 2: the texture tiles 3 x 3, and
    // u and v are swapped against x and z (u follows z, v follows x).
    json mesh = {{"type", "mesh"},
                 {"positions", {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1}},
                 {"indices", {0, 2, 1, 0, 3, 2}},
                 {"uvs", {-1, -1, -1, 2, 2, 2, 2, -1}}};
    json scene = sceneWith(test::topDownCamera(0, 0, 0.95),
                           {{"type", "diffuse"}, {"albedo", {{"texture", "checker.exr"}}}}, mesh);
    Scene loaded = test::sceneFromJson(scene, "textures/mesh/scene");
    Image image = test::renderScene(loaded);
    Expected e = expectedImage(loaded, [&](glm::dvec3 o, glm::dvec3 d, int c) -> std::optional<double> {
        glm::dvec3 x = planeHit(o, d);
        return tex.bilinear(-1 + 1.5 * (x.z + 1), -1 + 1.5 * (x.x + 1), c);
    });
    EXPECT_EQ(compare(image, e, "mesh"), 0);
}

TEST(Textures, MeshWithoutUvsReadsUvZero) {
    auto dir = test::freshOutputDir("textures", "mesh-no-uvs");
    CpuTexture tex = checkerboard();
    writeExrTexture(tex, dir / "checker.exr");
    json mesh = {{"type", "mesh"}, {"positions", {-1, 0, -1, 1, 0, -1, 1, 0, 1}}, {"indices", {0, 2, 1}}};
    json scene = sceneWith(test::topDownCamera(0.3, -0.3, 0.3),
                           {{"type", "diffuse"}, {"albedo", {{"texture", "checker.exr"}}}}, mesh);
    Scene loaded = test::sceneFromJson(scene, "textures/mesh-no-uvs/scene");
    Image image = test::renderScene(loaded);
    // uv (0, 0) is the corner between texels (3, 2), (0, 2), (3, 0) and (0, 0), equally weighted.
    Expected e = expectedImage(
        loaded, [&](glm::dvec3, glm::dvec3, int c) -> std::optional<double> { return tex.bilinear(0, 0, c); });
    EXPECT_EQ(compare(image, e, "mesh-no-uvs"), 0);
}

TEST(Textures, SphereCoordinatesFollowTheContract) {
    auto dir = test::freshOutputDir("textures", "sphere");
    // 8 x 4 texels: longitude and latitude bands of distinct values.
    CpuTexture tex;
    tex.width = 8;
    tex.height = 4;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x)
            tex.rgba.insert(tex.rgba.end(),
                            {0.0625f + 0.125f * float(x), 0.125f + 0.25f * float(y), (x + y) % 2 ? 1.0f : 0.0f, 1.0f});
    writeExrTexture(tex, dir / "bands.exr");
    const glm::dvec3 centre(0.2, 0.1, -0.3);
    const double radius = 1.0;
    // Seen from above and behind, so that the seam (u = 0: x = 0, z < 0 from the centre)
    // and the north pole (v = 0) are in view.
    json camera = {{"eye", {1.0, 3.0, -3.5}}, {"target", {0.2, 0.1, -0.3}}, {"up", {0, 1, 0}}, {"fov_y", 45}};
    json sphere = {{"type", "sphere"}, {"center", {centre.x, centre.y, centre.z}}, {"radius", radius}};
    json scene = sceneWith(camera, {{"type", "diffuse"}, {"albedo", {{"texture", "bands.exr"}}}}, sphere);
    Scene loaded = test::sceneFromJson(scene, "textures/sphere/scene");
    Image image = test::renderScene(loaded);
    Expected e = expectedImage(loaded, [&](glm::dvec3 o, glm::dvec3 d, int c) -> std::optional<double> {
        glm::dvec3 oc = o - centre;
        double b = glm::dot(oc, d), disc = b * b - (glm::dot(oc, oc) - radius * radius);
        if (disc < 0) return std::nullopt;
        glm::dvec3 n = glm::normalize(oc + (-b - std::sqrt(disc)) * d);
        double u = std::atan2(n.x, -n.z) / (2 * M_PI);
        if (u < 0) u += 1;
        double v = std::acos(std::clamp(n.y, -1.0, 1.0)) / M_PI;
        return tex.bilinear(u, v, c);
    });
    // Pixels astride the seam see texels from both of its sides blended by the repeat;
    // the pole's pixels squeeze the whole top row: both are compared like any other.
    EXPECT_EQ(compare(image, e, "sphere"), 0);
}

TEST(Textures, SrgbPngIsDecodedBeforeFiltering) {
    auto dir = test::freshOutputDir("textures", "srgb");
    // 2 x 1 texels with sRGB codes 40 and 220 (per channel different): the filtered value
    // halfway between them is the mean of the decoded values, not the decoded mean code.
    const uint8_t codes[2][3] = {{40, 128, 255}, {220, 16, 0}};
    std::vector<uint8_t> rgb;
    for (auto& t : codes) rgb.insert(rgb.end(), t, t + 3);
    writePngRgb8(dir / "pair.png", 2, 1, rgb);
    CpuTexture tex;
    tex.width = 2;
    tex.height = 1;
    for (auto& t : codes)
        for (int c = 0; c < 4; ++c) {
            // Rounded to half as the GPU holds it.
            float linear = c < 3 ? srgbToLinear(t[c] / 255.0f) : 1.0f;
            tex.rgba.push_back(glm::unpackHalf1x16(glm::packHalf1x16(linear)));
        }
    json quad = {{"type", "quad"}, {"origin", {-1, 0, -1}}, {"edge_u", {2, 0, 0}}, {"edge_v", {0, 0, 2}}};
    json scene =
        sceneWith(test::topDownCamera(0, 0, 0.95), {{"type", "diffuse"}, {"albedo", {{"texture", "pair.png"}}}}, quad);
    Scene loaded = test::sceneFromJson(scene, "textures/srgb/scene");
    Image image = test::renderScene(loaded);
    Expected e = expectedImage(loaded, [&](glm::dvec3 o, glm::dvec3 d, int c) -> std::optional<double> {
        glm::dvec3 x = planeHit(o, d);
        return tex.bilinear((x.x + 1) / 2, (x.z + 1) / 2, c);
    });
    EXPECT_EQ(compare(image, e, "srgb"), 0);
    // Not sRGB-decoded, the middle of the image would be far off.
    const float* middle = image.pixel(kSize / 2, kSize / 2);
    EXPECT_GT(std::fabs(middle[0] - 0.5 * (40 + 220) / 255.0), 0.1);
}

namespace {

// A 1 x 1 EXR texture of one colour.
void writeConstantExr(const std::filesystem::path& file, float r, float g, float b) {
    Image texel;
    texel.width = texel.height = 1;
    texel.rgb = {r, g, b};
    writeExr(file, texel);
}

// A quad seen from above at an angle, lit by a point light and the white environment, at
// 4 spp: `material` as textured or plain, rendered with the same samples.
Image renderLitQuad(const json& material, const std::string& group, const std::string& name) {
    json camera = {{"eye", {0, 3, 3}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_y", 40}};
    json quad = {{"type", "quad"}, {"origin", {-1, 0, -1}}, {"edge_u", {2, 0, 0}}, {"edge_v", {0, 0, 2}}};
    json scene = sceneWith(camera, material, quad);
    scene["lights"].push_back({{"type", "point"}, {"position", {0.5, 2, 1}}, {"power", 30}});
    scene["sampler"]["spp"] = 4;
    return test::renderScene(test::sceneFromJson(scene, "textures/" + group + "/" + name));
}

// The largest per-channel difference of a from b, relative to b (plus 1e-3 near black).
double worstRelativeDifference(const Image& a, const Image& b) {
    double worst = 0;
    for (size_t k = 0; k < a.rgb.size(); ++k)
        worst = std::max(worst, double(std::fabs(a.rgb[k] - b.rgb[k])) / (std::fabs(b.rgb[k]) + 1e-3));
    return worst;
}

}  // namespace

TEST(Textures, PhongKdAndKsSlotsTakeScaleTimesTexture) {
    // A textured Phong material whose textures are constant renders as the material with
    // those constants: the same kernel decisions, so the same pixels up to float rounding.
    // The scales alone (what the host records for a textured field) would differ, as would
    // a value put into the wrong slot. The last case's EXR texels of 2 give kd 0.8 and ks
    // 0.5, whose sum exceeds 1 (the scales' 0.65 does not): ks is lowered to 0.2.
    auto dir = test::freshOutputDir("textures", "phong");
    writeConstantExr(dir / "half.exr", 0.5f, 0.5f, 0.5f);
    writeConstantExr(dir / "two.exr", 2.0f, 2.0f, 2.0f);
    auto render = [](const json& material, const std::string& name) { return renderLitQuad(material, "phong", name); };
    struct Case {
        json textured, plain;
    };
    std::vector<Case> cases = {
        {{{"type", "phong"},
          {"kd", {{"texture", "half.exr"}, {"scale", {0.6, 0.2, 0.4}}}},
          {"ks", 0.4},
          {"exponent", 30}},
         {{"type", "phong"}, {"kd", {0.3, 0.1, 0.2}}, {"ks", 0.4}, {"exponent", 30}}},
        {{{"type", "phong"},
          {"kd", 0.3},
          {"ks", {{"texture", "half.exr"}, {"scale", {0.5, 0.7, 0.2}}}},
          {"exponent", 30}},
         {{"type", "phong"}, {"kd", 0.3}, {"ks", {0.25, 0.35, 0.1}}, {"exponent", 30}}},
        {{{"type", "phong"},
          {"kd", {{"texture", "two.exr"}, {"scale", 0.4}}},
          {"ks", {{"texture", "two.exr"}, {"scale", 0.25}}},
          {"exponent", 30}},
         {{"type", "phong"}, {"kd", 0.8}, {"ks", 0.2}, {"exponent", 30}}},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        Image a = render(cases[i].textured, "textured-" + std::to_string(i));
        Image b = render(cases[i].plain, "plain-" + std::to_string(i));
        ASSERT_EQ(a.rgb.size(), b.rgb.size());
        EXPECT_LT(worstRelativeDifference(a, b), 1e-4) << "case " << i;
    }
}

TEST(Textures, PbrBaseColorMetallicAndRoughnessSlotsTakeScaleTimesTexture) {
    // As for Phong above: a pbr material whose textures are constant renders as the material
    // with those constants. Number fields read the texture's first channel (red), so the
    // texture of colour (1, 0, 0) gives the scale itself, where green or blue would give 0.
    auto dir = test::freshOutputDir("textures", "pbr");
    writeConstantExr(dir / "half.exr", 0.5f, 0.5f, 0.5f);
    writeConstantExr(dir / "red.exr", 1.0f, 0.0f, 0.0f);
    auto render = [](const json& material, const std::string& name) { return renderLitQuad(material, "pbr", name); };
    auto pbr = [](const json& baseColor, const json& metallic, const json& roughness) {
        return json{{"type", "pbr"}, {"base_color", baseColor}, {"metallic", metallic}, {"roughness", roughness}};
    };
    auto tex = [](const char* file, const json& scale) { return json{{"texture", file}, {"scale", scale}}; };
    const json orange = {0.9, 0.6, 0.3};
    struct Case {
        json textured, plain;
    };
    std::vector<Case> cases = {
        {pbr(tex("half.exr", {0.6, 0.2, 0.4}), 0.5, 0.4), pbr({0.3, 0.1, 0.2}, 0.5, 0.4)},
        {pbr(orange, tex("half.exr", 0.8), 0.4), pbr(orange, 0.4, 0.4)},
        {pbr(orange, 0.5, tex("half.exr", 0.6)), pbr(orange, 0.5, 0.3)},
        {pbr(orange, tex("red.exr", 0.7), tex("red.exr", 0.35)), pbr(orange, 0.7, 0.35)},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        Image a = render(cases[i].textured, "textured-" + std::to_string(i));
        Image b = render(cases[i].plain, "plain-" + std::to_string(i));
        ASSERT_EQ(a.rgb.size(), b.rgb.size());
        EXPECT_LT(worstRelativeDifference(a, b), 1e-4) << "case " << i;
    }
    // The comparison tells such values apart: half the metallic factor changes the image.
    Image metal = render(pbr(orange, 0.8, 0.4), "metallic-0.8");
    Image lessMetal = render(pbr(orange, 0.4, 0.4), "metallic-0.4");
    EXPECT_GT(worstRelativeDifference(metal, lessMetal), 1e-2);
}

namespace {

// sRGB codes of a 4 x 3 RGB texture, every texel and channel different.
std::vector<uint8_t> codes4x3() {
    std::vector<uint8_t> rgb;
    for (int i = 0; i < 12; ++i)
        rgb.insert(rgb.end(), {uint8_t(20 * i + 5), uint8_t(250 - 17 * i), uint8_t((i % 3) * 100 + 20)});
    return rgb;
}

std::string fileBytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A glTF quad over [-1, 1]^2 in y = 0 (facing +y) with TEXCOORD_0 = (x + 1, 0.75 (z + 1))
// (so the texture repeats along u), base colour factor (1, 0.5, 0.25) times a texture whose
// image comes from `source`: "uri" (an external PNG), "data" (a data URI) or "view" (a GLB
// buffer view). `wrap` is the sampler's wrapS.
std::string texturedQuadModel(const std::filesystem::path& dir, const std::string& source, int wrap = 10497) {
    test::GltfBuilder b;
    std::vector<float> uvs = {0, 0, 2, 0, 2, 1.5f, 0, 1.5f};
    json primitive = {{"attributes",
                       {{"POSITION", b.positions({-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1})},
                        {"TEXCOORD_0", b.addAccessor(uvs.data(), uvs.size() * 4, 5126, 4, "VEC2")}}},
                      {"indices", b.indices({0, 2, 1, 0, 3, 2})},
                      {"material", 0}};
    b.addMeshNode(primitive);
    b.doc["materials"] = {
        {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0.5, 0.25, 1}}, {"baseColorTexture", {{"index", 0}}}}}}};
    b.doc["samplers"] = {{{"wrapS", wrap}, {"wrapT", 10497}}};
    b.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    writePngRgb8(dir / "texture.png", 4, 3, codes4x3());
    std::string png = fileBytes(dir / "texture.png");
    if (source == "uri") {
        b.doc["images"] = {{{"uri", "texture.png"}}};
    } else if (source == "data") {
        b.doc["images"] = {
            {{"uri", "data:image/png;base64," + test::base64(std::vector<uint8_t>(png.begin(), png.end()))}}};
    } else {
        while (b.bin.size() % 4) b.bin.push_back(0);
        b.doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", b.bin.size()}, {"byteLength", png.size()}});
        b.bin.insert(b.bin.end(), png.begin(), png.end());
        b.doc["images"] = {{{"bufferView", b.doc["bufferViews"].size() - 1}, {"mimeType", "image/png"}}};
    }
    return source == "view" ? b.glb() : b.gltf();
}

}  // namespace

namespace {

// glTF sampler wrap modes (the OpenGL enums glTF 2.0 section 5.26 names).
constexpr int kGlRepeat = 10497, kGlClampToEdge = 33071, kGlMirroredRepeat = 33648;

// Renders the glTF quad of texturedQuadModel (image from `source`, sampler wrapS `glWrap`)
// and compares it with the CPU evaluation of its base colour texture, wrapped along u as
// `wrap` says (the quad's u runs over [0, 2], so the second half shows the wrapping).
// `transform`, if not null, is the base colour texture's KHR_texture_transform and `uvMap` the
// coordinates it maps the quad's uv to (with repeat wrapping: the CPU lookup wraps v so).
void expectGltfQuadShowsTexture(const std::string& source, int glWrap, TextureWrap wrap, const std::string& name,
                                const json& transform = nullptr,
                                const std::function<glm::dvec2(glm::dvec2)>& uvMap = nullptr) {
    CpuTexture tex;
    tex.width = 4;
    tex.height = 3;
    std::vector<uint8_t> codes = codes4x3();
    for (size_t i = 0; i < codes.size(); i += 3) {
        for (int c = 0; c < 3; ++c)
            tex.rgba.push_back(glm::unpackHalf1x16(glm::packHalf1x16(srgbToLinear(codes[i + c] / 255.0f))));
        tex.rgba.push_back(1.0f);
    }
    const glm::dvec3 factor(1, 0.5, 0.25);
    auto dir = test::freshOutputDir("textures", name);
    std::string model = source == "view" ? "quad.glb" : "quad.gltf";
    std::string bytes = texturedQuadModel(dir, source, glWrap);
    if (!transform.is_null()) {
        json doc = json::parse(bytes);
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"] =
            transform;
        doc["extensionsUsed"] = {"KHR_texture_transform"};
        bytes = doc.dump();
    }
    test::writeFile(dir / model, bytes);
    if (source != "uri") std::filesystem::remove(dir / "texture.png");  // only in the model
    json scene = {{"camera", test::topDownCamera(0, 0, 0.95)},
                  {"film", {{"width", kSize}, {"height", kSize}}},
                  {"sampler", {{"spp", kSpp}, {"seed", 5}, {"type", "independent"}}},
                  {"shapes", json::array({{{"type", "gltf"}, {"file", model}}})},
                  {"lights", json::array({{{"type", "environment"}, {"radiance", 1}}})},
                  // glTF materials are pbr (SCENE_FORMAT.md v2); the ao integrator shades
                  // with their base colour as the albedo, which an unoccluded plane returns
                  // exactly under cosine sampling: the base colour alone is checked here.
                  {"integrator", {{"type", "ao"}}}};
    Scene loaded = test::sceneFromJson(scene, "textures/" + name + "/scene");
    ASSERT_EQ(loaded.textures.size(), 1u) << name;
    EXPECT_TRUE(loaded.textures[0].srgb);
    Image image = test::renderScene(loaded);
    Expected e = expectedImage(loaded, [&](glm::dvec3 o, glm::dvec3 d, int c) -> std::optional<double> {
        glm::dvec3 x = planeHit(o, d);
        glm::dvec2 uv(x.x + 1, 0.75 * (x.z + 1));
        if (uvMap) uv = uvMap(uv);
        return factor[c] * tex.bilinear(uv.x, uv.y, c, wrap);
    });
    EXPECT_EQ(compare(image, e, name), 0) << name;
}

}  // namespace

TEST(Textures, GltfBaseColorTextureFromEachImageSource) {
    for (std::string source : {"uri", "data", "view"})
        expectGltfQuadShowsTexture(source, kGlRepeat, TextureWrap::Repeat, "gltf-" + source);
}

TEST(Textures, GltfSamplersClampToEdgeAndMirror) {
    expectGltfQuadShowsTexture("data", kGlClampToEdge, TextureWrap::Clamp, "gltf-clamp");
    expectGltfQuadShowsTexture("data", kGlMirroredRepeat, TextureWrap::Mirror, "gltf-mirror");
}

// KHR_texture_transform (glTF extension README; rotation as KhronosGroup/glTF issue 1563 and
// the TextureTransformTest sample read it, counter-clockwise in u-right, v-down uv space):
// uv' = T(offset) R(rotation) S(scale) uv, i.e.
//   u' = cos sx u + sin sy v + ox,   v' = -sin sx u + cos sy v + oy,
// evaluated here in double and looked up on the CPU: the quad's texels land where the
// transformed coordinates say, tiled (repeat) over the rotated, scaled and shifted range.
TEST(Textures, GltfTextureTransformMovesTheLookupByOffsetRotationAndScale) {
    const double ox = 0.3, oy = -0.2, r = 0.4, sx = 1.5, sy = 0.75;
    json transform = {{"offset", {ox, oy}}, {"rotation", r}, {"scale", {sx, sy}}};
    expectGltfQuadShowsTexture("data", kGlRepeat, TextureWrap::Repeat, "gltf-transform", transform, [&](glm::dvec2 uv) {
        return glm::dvec2(std::cos(r) * sx * uv.x + std::sin(r) * sy * uv.y + ox,
                          -std::sin(r) * sx * uv.x + std::cos(r) * sy * uv.y + oy);
    });
    // Offset alone, and texCoord 0 given explicitly: the same rule without rotation.
    expectGltfQuadShowsTexture("data", kGlRepeat, TextureWrap::Repeat, "gltf-offset",
                               {{"offset", {0.5, 0.25}}, {"texCoord", 0}},
                               [](glm::dvec2 uv) { return uv + glm::dvec2(0.5, 0.25); });
}

TEST(Textures, GltfTextureTransformErrorsNameTheirPath) {
    auto dir = test::freshOutputDir("textures", "gltf-transform-bad");
    const json base = json::parse(texturedQuadModel(dir, "data"));
    const std::string at = "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform";
    const std::vector<std::pair<json, std::string>> cases = {
        {{{"offset", {1, "x"}}}, at + ".offset[1]: expected a number"},
        {{{"offset", {1}}}, at + ".offset: expected 2 numbers"},
        {{{"scale", {1, 1e30}}}, at + ".scale[1]: must be finite and at most 1e8 in magnitude"},
        {{{"rotation", "half"}}, at + ".rotation: expected a number"},
        {{{"texCoord", -1}}, at + ".texCoord: expected a non-negative integer"},
    };
    for (const auto& [transform, message] : cases) {
        json doc = base;
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"] =
            transform;
        auto file = test::writeFile(dir / "bad.gltf", doc.dump());
        EXPECT_EQ(test::loadError(file), file.string() + ": " + message) << transform.dump();
    }
    // A texCoord override other than 0 is read with TEXCOORD_0, as a textureInfo's is, with a note.
    json doc = base;
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"] = {
        {"texCoord", 1}};
    auto file = test::writeFile(dir / "set1.gltf", doc.dump());
    Scene scene = loadScene(file);
    bool noted = false;
    for (const std::string& n : scene.notes)
        noted |= n == file.string() + ": textures using TEXCOORD_1 are read with TEXCOORD_0";
    EXPECT_TRUE(noted);
}

// Scenes without a transform (or with an identity one) keep the short texture references
// and compile the transform out: their kernels are the kernels of before.
TEST(Textures, OnlyScenesWithATextureTransformCarryTransforms) {
    auto dir = test::freshOutputDir("textures", "gltf-transform-bits");
    json doc = json::parse(texturedQuadModel(dir, "data"));
    auto bits = [&](const json& transform) {
        json d = doc;
        if (!transform.is_null())
            d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"] =
                transform;
        Scene scene = loadScene(test::writeFile(dir / "quad.gltf", d.dump()));
        SceneArrays arrays = buildSceneArrays(scene);
        // One material header, then one reference of TEXTURE_REF_TEXELS (+ the transform's).
        const size_t refTexels = arrays.textures.materialTextures.size() - scene.materials.size();
        return std::make_pair(makeKernelOptions(scene, arrays).textures, refTexels);
    };
    EXPECT_EQ(bits(nullptr), std::make_pair(TEXTURES_ON, size_t(gpu::TEXTURE_REF_TEXELS)));
    EXPECT_EQ(bits(json::object()), std::make_pair(TEXTURES_ON, size_t(gpu::TEXTURE_REF_TEXELS)));
    EXPECT_EQ(bits({{"scale", {2, 1}}}),
              std::make_pair(TEXTURES_ON | TEXTURES_TRANSFORMED,
                             size_t(gpu::TEXTURE_REF_TEXELS + gpu::TEXTURE_TRANSFORM_TEXELS)));
}

TEST(Textures, GltfMetallicRoughnessTextureFeedsPbrMetallicFromBlueAndRoughnessFromGreen) {
    auto dir = test::freshOutputDir("textures", "gltf-metallic-roughness");
    json model = json::parse(texturedQuadModel(dir, "uri"));
    json& pbr = model["materials"][0]["pbrMetallicRoughness"];
    pbr["metallicFactor"] = 0.25;
    pbr["roughnessFactor"] = 0.5;
    pbr["metallicRoughnessTexture"] = {{"index", 0}};
    test::writeFile(dir / "quad.gltf", model.dump());
    Scene scene = loadScene(dir / "quad.gltf");
    ASSERT_FALSE(scene.materials.empty());
    const Material& m = scene.materials.back();
    EXPECT_EQ(m.type, MaterialType::Pbr);
    // One image, decoded twice: as sRGB colour (base colour) and as linear data.
    EXPECT_EQ(scene.textures.size(), 2u);
    bool metallic = false, roughness = false, baseColor = false;
    for (const MaterialTexture& t : m.textures) {
        if (t.slot == TextureSlot::KsX) {
            metallic = true;
            EXPECT_EQ(t.channel, 2u);  // blue
            EXPECT_FLOAT_EQ(t.scale.x, 0.25f);
            EXPECT_FALSE(scene.textures[t.texture].srgb);
        } else if (t.slot == TextureSlot::KsY) {
            roughness = true;
            EXPECT_EQ(t.channel, 1u);  // green
            EXPECT_FLOAT_EQ(t.scale.x, 0.5f);
            EXPECT_FALSE(scene.textures[t.texture].srgb);
        } else if (t.slot == TextureSlot::Kd) {
            baseColor = true;
            EXPECT_TRUE(scene.textures[t.texture].srgb);
        }
    }
    EXPECT_TRUE(metallic && roughness && baseColor);
}

TEST(Textures, GltfBadImagesNameTheModelAndImage) {
    auto dir = test::freshOutputDir("textures", "gltf-bad");
    std::string model = texturedQuadModel(dir, "data");
    json doc = json::parse(model);
    doc["images"][0]["uri"] = "data:image/png;base64," +
                              test::base64({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 1, 2, 3});
    test::writeFile(dir / "corrupt.gltf", doc.dump());
    std::string error = test::loadError(dir / "corrupt.gltf");
    EXPECT_NE(error.find("corrupt.gltf: images[0]: cannot decode PNG image"), std::string::npos) << error;

    doc["images"][0]["uri"] = "data:image/gif;base64," + test::base64({'G', 'I', 'F', '8', '9', 'a'});
    test::writeFile(dir / "gif.gltf", doc.dump());
    error = test::loadError(dir / "gif.gltf");
    EXPECT_NE(error.find("gif.gltf: images[0]: unsupported image format"), std::string::npos) << error;

    doc["images"][0]["uri"] = "missing.png";
    test::writeFile(dir / "missing.gltf", doc.dump());
    error = test::loadError(dir / "missing.gltf");
    EXPECT_NE(error.find("missing.gltf"), std::string::npos) << error;
    EXPECT_NE(error.find("missing.png"), std::string::npos) << error;

    json bad = json::parse(texturedQuadModel(dir, "data"));
    bad["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 4;
    test::writeFile(dir / "no-texture.gltf", bad.dump());
    error = test::loadError(dir / "no-texture.gltf");
    EXPECT_NE(error.find("materials[0].pbrMetallicRoughness.baseColorTexture.index: texture 4 does not exist"),
              std::string::npos)
        << error;
}

// Debian's assimp-testmodels (tools/setup installs it): the Khronos BoxTextured sample in
// its three packagings (external PNG, GLB, embedded data URI) loads its texture and
// renders the same image from each.
TEST(Textures, AssimpBoxTexturedRendersFromEachPackagingWithItsSamplers) {
    const std::filesystem::path root = "/usr/share/assimp/models/glTF2";
    const std::vector<std::filesystem::path> models = {root / "BoxTextured-glTF/BoxTextured.gltf",
                                                       root / "BoxTextured-glTF-Binary/BoxTextured.glb",
                                                       root / "BoxTextured-glTF-Embedded/BoxTextured.gltf"};
    for (const auto& m : models)
        ASSERT_TRUE(std::filesystem::exists(m)) << m << " (install assimp-testmodels: tools/setup)";
    ImageFile png = readImageFile(root / "BoxTextured-glTF/CesiumLogoFlat.png", ColorDecode::Srgb);
    std::vector<Image> images;
    for (const auto& m : models) {
        Scene scene = loadScene(m, {{"film.width", "48"}, {"film.height", "48"}, {"sampler.spp", "4"}});
        ASSERT_EQ(scene.textures.size(), 1u) << m;
        EXPECT_EQ(scene.textures[0].width, png.width);
        EXPECT_EQ(scene.textures[0].height, png.height);
        // The decoded texels are the PNG's, sRGB-decoded and rounded to half.
        for (size_t i = 0; i < png.rgba.size(); i += 97)
            EXPECT_EQ(scene.textures[0].texels[i], glm::packHalf1x16(png.rgba[i])) << m << " texel value " << i;
        size_t textured = 0;
        for (const Material& mat : scene.materials) textured += mat.textures.size();
        EXPECT_EQ(textured, 1u) << m;
        images.push_back(test::renderScene(scene));
    }
    // The .glb and the embedded .gltf ask for REPEAT; BoxTextured-glTF asks for
    // MIRRORED_REPEAT along u and CLAMP_TO_EDGE along v, which differ from REPEAT only where
    // bilinear filtering reaches past the image's edge: a thin band of pixels.
    EXPECT_EQ(images[2].rgb, images[1].rgb) << models[2];
    size_t differing = 0;
    for (size_t k = 0; k < images[0].rgb.size(); k += 3)
        differing += images[0].rgb[k] != images[1].rgb[k] || images[0].rgb[k + 1] != images[1].rgb[k + 1] ||
                     images[0].rgb[k + 2] != images[1].rgb[k + 2];
    std::printf("BoxTextured: %zu of %zu pixels differ between mirror/clamp and repeat\n", differing,
                images[0].rgb.size() / 3);
    EXPECT_GT(differing, 0u);
    EXPECT_LT(differing, images[0].rgb.size() / 3 / 4);
    // The logo's texture shows: the box's pixels are not one colour.
    float lo = 1e30f, hi = -1e30f;
    for (float v : images[0].rgb) lo = std::min(lo, v), hi = std::max(hi, v);
    EXPECT_GT(hi - lo, 0.2f);
}
