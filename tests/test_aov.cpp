// AOV layers (SCENE_FORMAT.md "AOVs (v3)") against closed forms. The camera at (0, 0, 3)
// looks down -z at a unit sphere at the origin in front of a 3 x 3 quad in the plane
// z = -2; the film's corners see past the quad. For a camera ray d (unit) from the eye e,
// the plane is hit at t = 5 / -d.z and the sphere where |e + t d| = 1, the nearer root;
// the sphere's normal there is the hit point itself, the plane's (0, 0, 1). A pixel's
// expected float AOV is the closed form averaged over the pixel (a 16 x 16 grid of
// directions); the tolerance is z times the closed form's spread over the pixel over
// sqrt(spp) (independent samples), plus float rounding.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr int kSize = 15, kSpp = 64, kGrid = 16;
constexpr uint32_t kNoId = 4294967295u;
const glm::dvec3 kEye(0, 0, 3);

json aovScene(const json& aovs, int spp = kSpp, int seed = 3) {
    return {
        {"camera", {{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_y", 40}}},
        {"film", {{"width", kSize}, {"height", kSize}, {"aovs", aovs}}},
        {"sampler", {{"spp", spp}, {"seed", seed}, {"type", "independent"}}},
        {"materials",
         {{"b_plane", {{"type", "diffuse"}, {"albedo", {0.2, 0.4, 0.6}}}},
          {"a_ball", {{"type", "phong"}, {"kd", {0.1, 0.2, 0.3}}, {"ks", {0.3, 0.1, 0.05}}, {"exponent", 10}}}}},
        {"shapes",
         {{{"type", "quad"},
           {"origin", {-1.5, -1.5, -2}},
           {"edge_u", {3, 0, 0}},
           {"edge_v", {0, 3, 0}},
           {"material", "b_plane"}},
          {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "a_ball"}},
          // A sphere light beside the camera, out of its view: shadows and MIS noise.
          {{"type", "sphere"}, {"center", {2, 2, 3}}, {"radius", 0.5}, {"power", 200}}}},
    };
}

// The renderer's camera ray through film point (fx, fy) in [0, 1]^2 (kernel_common.glsl,
// cameraRay; right = (1, 0, 0), up = (0, 1, 0), forward = (0, 0, -1) for this camera).
glm::dvec3 rayDir(double fx, double fy) {
    const double tanHalf = std::tan(20.0 * M_PI / 180.0);
    return glm::normalize(glm::dvec3((2 * fx - 1) * tanHalf, (1 - 2 * fy) * tanHalf, -1));
}

// What the first hit along d is: 0 plane, 1 sphere, nullopt a miss; t and the facing normal.
struct FirstHit {
    int shape;
    double t;
    glm::dvec3 normal;
};
std::optional<FirstHit> firstHit(glm::dvec3 d) {
    const double b = glm::dot(kEye, d), c = glm::dot(kEye, kEye) - 1, disc = b * b - c;
    if (disc >= 0) {
        const double t = -b - std::sqrt(disc);
        return FirstHit{1, t, kEye + t * d};
    }
    const double t = 5 / -d.z;
    const glm::dvec3 p = kEye + t * d;
    if (std::abs(p.x) <= 1.5 && std::abs(p.y) <= 1.5) return FirstHit{0, t, {0, 0, 1}};
    return std::nullopt;
}

// The mean and spread (standard deviation) over pixel (x, y) of f(d), or nullopt where some
// grid ray or corner meets another shape than the centre ray (a silhouette pixel).
struct PixelStats {
    double mean, sd;
};
std::optional<PixelStats> overPixel(int x, int y, const std::function<double(glm::dvec3, const FirstHit&)>& f) {
    const auto centre = firstHit(rayDir((x + 0.5) / kSize, (y + 0.5) / kSize));
    if (!centre) return std::nullopt;
    for (int cy = 0; cy <= 1; ++cy)
        for (int cx = 0; cx <= 1; ++cx) {
            auto h = firstHit(rayDir((x + cx) / double(kSize), (y + cy) / double(kSize)));
            if (!h || h->shape != centre->shape) return std::nullopt;
        }
    double sum = 0, sum2 = 0;
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            const glm::dvec3 d = rayDir((x + (i + 0.5) / kGrid) / kSize, (y + (j + 0.5) / kGrid) / kSize);
            const auto h = firstHit(d);
            if (!h || h->shape != centre->shape) return std::nullopt;
            const double v = f(d, *h);
            sum += v;
            sum2 += v * v;
        }
    const double n = kGrid * kGrid, mean = sum / n;
    return PixelStats{mean, std::sqrt(std::max(sum2 / n - mean * mean, 0.0))};
}

const AovLayer& layer(const Image& image, const std::string& name) {
    for (const AovLayer& l : image.aovs)
        if (l.name == name) return l;
    throw std::runtime_error("no layer " + name);
}

// The scene of aovScene with 64 small triangles behind the camera, out of its view and of
// every shadow ray: more primitives than a kernel holds inline, so it renders through the
// BVH, in the kernel that traces camera rays in pairs and hands each sample's first hit to
// the AOV layers (integrators/aov.glsl) instead of tracing it again.
json withHiddenTriangles(json scene) {
    json positions = json::array(), indices = json::array();
    for (int k = 0; k < 64; ++k) {
        const double x = -3.2 + 0.1 * k;
        for (double v : {x, 0.0, 6.0, x + 0.05, 0.0, 6.0, x, 0.05, 6.0}) positions.push_back(v);
        for (int c = 0; c < 3; ++c) indices.push_back(3 * k + c);
    }
    scene["shapes"].push_back({{"type", "mesh"}, {"positions", positions}, {"indices", indices}});
    return scene;
}

void expectClosedForms(const json& scene, const std::string& name) {
    const Image image = test::renderJson(scene, name);
    ASSERT_EQ(image.aovs.size(), 4u);
    const double z = test::zScore(1e-6, kSize * kSize * 10);
    int checked = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const size_t i = size_t(y) * kSize + x;
            auto check = [&](const std::string& name, int channel, double value, const PixelStats& s) {
                const double tol = z * s.sd / std::sqrt(double(kSpp)) + 1e-5 * (1 + std::abs(s.mean));
                EXPECT_NEAR(value, s.mean, tol) << name << " channel " << channel << " pixel " << x << "," << y;
            };
            auto depth = overPixel(x, y, [](glm::dvec3, const FirstHit& h) { return h.t; });
            if (!depth) continue;
            ++checked;
            check("depth", 0, layer(image, "depth").floats[i], *depth);
            for (int c = 0; c < 3; ++c) {
                check("position", c, layer(image, "position").floats[3 * i + c],
                      *overPixel(x, y, [c](glm::dvec3 d, const FirstHit& h) { return (kEye + h.t * d)[c]; }));
                check("normal", c, layer(image, "normal").floats[3 * i + c],
                      *overPixel(x, y, [c](glm::dvec3, const FirstHit& h) { return h.normal[c]; }));
            }
            const bool sphere = firstHit(rayDir((x + 0.5) / kSize, (y + 0.5) / kSize))->shape == 1;
            const glm::dvec3 albedo = sphere ? glm::dvec3(0.4, 0.3, 0.35) : glm::dvec3(0.2, 0.4, 0.6);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(layer(image, "albedo").floats[3 * i + c], albedo[c], 1e-6) << "albedo " << x << "," << y;
        }
    EXPECT_GT(checked, kSize * kSize / 2);
    // The corner pixels see nothing: depth +inf, the rest 0.
    EXPECT_EQ(layer(image, "depth").floats[0], std::numeric_limits<float>::infinity());
    for (int c = 0; c < 3; ++c) EXPECT_EQ(layer(image, "normal").floats[c], 0.0f);
}

}  // namespace

TEST(Aov, DepthPositionNormalAndAlbedoMatchClosedForms) {
    expectClosedForms(aovScene({"albedo", "normal", "position", "depth"}), "aov-closed-forms");
}

TEST(Aov, DepthPositionNormalAndAlbedoMatchClosedFormsThroughTheBvh) {
    expectClosedForms(withHiddenTriangles(aovScene({"albedo", "normal", "position", "depth"})), "aov-closed-forms-bvh");
}

TEST(Aov, IdsFollowTheSceneOrderAndTheCentreRay) {
    const Image image = test::renderJson(aovScene({"shape_id", "primitive_id", "material_id"}, 4), "aov-ids");
    ASSERT_EQ(image.aovs.size(), 3u);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const size_t i = size_t(y) * kSize + x;
            const auto h = firstHit(rayDir((x + 0.5) / kSize, (y + 0.5) / kSize));
            // shapes: quad 0, sphere 1; sorted material keys: a_ball 0, b_plane 1.
            const uint32_t shape = h ? uint32_t(h->shape) : kNoId;
            const uint32_t material = h ? uint32_t(1 - h->shape) : kNoId;
            EXPECT_EQ(layer(image, "shape_id").ids[i], shape) << x << "," << y;
            EXPECT_EQ(layer(image, "material_id").ids[i], material) << x << "," << y;
            EXPECT_EQ(layer(image, "primitive_id").ids[i], h ? 0u : kNoId) << x << "," << y;
        }
}

// The variance layer estimates the variance of each pixel's mean; so does the spread of the
// means of independent renders (seeds). Both are unbiased, so their per-pixel difference has
// mean 0: a t-test over the pixels, its spread taken from the data.
TEST(Aov, VarianceMatchesTheSpreadOfIndependentRenders) {
    constexpr int kRenders = 16, kFewSpp = 4;
    const size_t pixels = size_t(kSize) * kSize;
    std::vector<double> sum(pixels * 3, 0), sum2(pixels * 3, 0), estimate(pixels * 3, 0);
    for (int k = 0; k < kRenders; ++k) {
        const Image image = test::renderJson(aovScene({"variance"}, kFewSpp, 100 + k), "aov-variance");
        for (size_t i = 0; i < pixels * 3; ++i) {
            sum[i] += image.rgb[i];
            sum2[i] += double(image.rgb[i]) * image.rgb[i];
            estimate[i] += layer(image, "variance").floats[i] / kRenders;
        }
    }
    std::vector<double> diffs;
    for (size_t i = 0; i < pixels * 3; ++i) {
        const double mean = sum[i] / kRenders;
        const double spread = (sum2[i] - kRenders * mean * mean) / (kRenders - 1);
        if (spread > 0 || estimate[i] > 0) diffs.push_back(estimate[i] - spread);
    }
    ASSERT_GT(diffs.size(), pixels);
    double m = 0, s2 = 0;
    for (double d : diffs) m += d / diffs.size();
    for (double d : diffs) s2 += (d - m) * (d - m) / (diffs.size() - 1);
    const double t = m / std::sqrt(s2 / diffs.size());
    EXPECT_LT(std::abs(t), test::tCritical(1e-4, 1, int(diffs.size()) - 1)) << "mean difference " << m;
}

TEST(Aov, NamesAreCheckedAtTheirJsonPath) {
    for (const json& aovs : {json{"depth", "albedoo"}, json{"depth", "depth"}, json{"depth", 3}}) {
        try {
            test::sceneFromJson(aovScene(aovs), "aov-bad-name");
            ADD_FAILURE() << aovs.dump() << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("film.aovs[1]"), std::string::npos) << e.what();
        }
    }
}

TEST(Aov, CommandLineWritesTheChannelsAndTheHeader) {
    const std::filesystem::path dir = std::filesystem::path(PENUMBRA_TEST_OUTPUT) / "aov-cli";
    std::filesystem::create_directories(dir);
    const std::string scene = (dir / "scene.json").string(), out = (dir / "out.exr").string();
    { std::ofstream(scene) << aovScene(json::array(), 4).dump(); }
    std::string err;
    ASSERT_EQ(test::runPenumbra("render '" + scene + "' --aov depth,shape_id,normal --quiet -o '" + out + "'", &err), 0)
        << err;
    Imf::InputFile file(out.c_str());
    const Imf::Header& header = file.header();
    for (const char* c : {"R", "G", "B", "depth.Z", "normal.X", "normal.Y", "normal.Z"}) {
        ASSERT_NE(header.channels().findChannel(c), nullptr) << c;
        EXPECT_EQ(header.channels().findChannel(c)->type, Imf::FLOAT) << c;
    }
    ASSERT_NE(header.channels().findChannel("shape_id"), nullptr);
    EXPECT_EQ(header.channels().findChannel("shape_id")->type, Imf::UINT);
    const auto* names = header.findTypedAttribute<Imf::StringAttribute>("penumbra:aovs");
    ASSERT_NE(names, nullptr);
    EXPECT_EQ(names->value(), "depth,shape_id,normal");
    std::vector<uint32_t> ids(size_t(kSize) * kSize);
    Imf::FrameBuffer frame;
    frame.insert("shape_id", Imf::Slice(Imf::UINT, reinterpret_cast<char*>(ids.data()), 4, 4 * kSize));
    file.setFrameBuffer(frame);
    file.readPixels(0, kSize - 1);
    EXPECT_EQ(ids[size_t(kSize / 2) * kSize + kSize / 2], 1u);  // the sphere
    EXPECT_EQ(ids[0], kNoId);

    const std::string bad = (dir / "bad.exr").string();
    EXPECT_EQ(test::runPenumbra("render '" + scene + "' --aov depth,bogus --quiet -o '" + bad + "'", &err), 2);
    EXPECT_NE(err.find("film.aovs[1]"), std::string::npos) << err;
    EXPECT_EQ(err.find('\n'), err.size() - 1) << err;
    EXPECT_FALSE(std::filesystem::exists(bad));
}
