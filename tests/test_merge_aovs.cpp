// penumbra merge of AOV layers (SCENE_FORMAT.md "AOVs (v3)", merge_aovs.h): partials merged
// are the layers of one render of all their samples, ids must agree, lists must match.
//
// Tolerances (float rounding only; the partials use exactly the full render's sample
// indices). The kernel sums a layer's samples one pass at a time in float, so a mean of n
// samples is off by at most (n - 1) u B + u B, where u = 2^-24 and B bounds the samples'
// magnitude (Higham, "Accuracy and Stability of Numerical Algorithms", 2002, eq. 4.4). The
// merge of pieces n_i (sum N) and the full render together are then off by at most
// (N + max n_i + 2) u B <= 2 (N + 1) u B. The variance, s^2 / N from the float sum of
// squares Q and the mean M, is off by at most about u (Q + 2 N M^2) / (N (N - 1)) per
// render, with Q / N = M^2 + (N - 1) var: 8 u (M^2 + (N - 1) var) covers both sides.
#include <cfloat>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr double kU = 1.0 / (1 << 24);  // unit roundoff of float

std::string q(const fs::path& p) { return test::shellQuoted(p); }

// A sphere in front of a quad that fills the whole view (every sample of every pixel hits:
// depth's mean over the samples that hit is then a mean over all, merged exactly), lit by
// a sphere light for noise.
json coveredScene() {
    return {
        {"camera", {{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_y", 40}}},
        {"film", {{"width", 12}, {"height", 9}}},
        {"materials",
         {{"wall", {{"type", "diffuse"}, {"albedo", {0.2, 0.4, 0.6}}}},
          {"ball", {{"type", "phong"}, {"kd", {0.1, 0.2, 0.3}}, {"ks", {0.3, 0.1, 0.05}}, {"exponent", 10}}}}},
        {"shapes",
         {{{"type", "quad"},
           {"origin", {-4, -4, -2}},
           {"edge_u", {8, 0, 0}},
           {"edge_v", {0, 8, 0}},
           {"material", "wall"}},
          {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "ball"}},
          {{"type", "sphere"}, {"center", {2, 2, 3}}, {"radius", 0.5}, {"power", 200}}}},
    };
}

const AovLayer& layer(const Image& image, const std::string& name) {
    for (const AovLayer& l : image.aovs)
        if (l.name == name) return l;
    throw std::runtime_error("no layer " + name);
}

AovLayer floats(const std::string& name, std::vector<std::string> channels, std::vector<float> values) {
    return {name, std::move(channels), std::move(values), {}};
}

}  // namespace

TEST(MergeAovs, PartialsMergeToTheFullRenderLayerByLayer) {
    const fs::path dir = test::freshOutputDir("merge-aovs", "cli");
    std::ofstream(dir / "scene.json") << coveredScene().dump();
    const std::string render =
        "render " + q(dir / "scene.json") +
        " --quiet --aov albedo,normal,position,depth,shape_id,primitive_id,material_id,variance ";
    std::string err;
    // Unequal pieces (3 + 5 spp), so that weighting them equally would show.
    ASSERT_EQ(test::runPenumbra(render + "--spp 3 -o " + q(dir / "a.exr"), &err), 0) << err;
    ASSERT_EQ(test::runPenumbra(render + "--spp 5 --set sampler.sample_offset=3 -o " + q(dir / "b.exr"), &err), 0)
        << err;
    ASSERT_EQ(test::runPenumbra(render + "--spp 8 -o " + q(dir / "full.exr"), &err), 0) << err;
    ASSERT_EQ(test::runPenumbra("merge " + q(dir / "a.exr") + " " + q(dir / "b.exr") + " -o " + q(dir / "m.exr"), &err),
              0)
        << err;
    const Image merged = readExr(dir / "m.exr"), full = readExr(dir / "full.exr");
    ASSERT_EQ(merged.aovs.size(), full.aovs.size());
    ASSERT_EQ(merged.aovs.size(), 8u);  // penumbra:aovs survived the merge, in its order
    const double n = 8;
    for (size_t l = 0; l < full.aovs.size(); ++l) {
        const AovLayer &m = merged.aovs[l], &f = full.aovs[l];
        ASSERT_EQ(m.name, f.name);
        ASSERT_EQ(m.channels, f.channels);
        EXPECT_EQ(m.ids, f.ids) << m.name;  // exactly
        ASSERT_EQ(m.floats.size(), f.floats.size()) << m.name;
        if (f.floats.empty()) continue;
        double bound = 0;  // B: the samples' magnitude, from the full render's layer
        for (float v : f.floats) bound = std::max(bound, double(std::abs(v)));
        for (size_t k = 0; k < f.floats.size(); ++k) {
            const double mean = full.rgb[k], var = f.floats[k];
            const double tol = m.name == "variance" ? 8 * kU * (mean * mean + (n - 1) * var)
                                                    : 2 * (n + 1) * kU * (bound + 1);
            ASSERT_NEAR(m.floats[k], f.floats[k], tol) << m.name << " value " << k;
        }
    }
    // The variance layer is not all zero: the test compares something.
    double total = 0;
    for (float v : layer(full, "variance").floats) total += v;
    EXPECT_GT(total, 0);
}

TEST(MergeAovs, OtherIdsOrOtherAovListsAreRefused) {
    const fs::path dir = test::freshOutputDir("merge-aovs", "refused");
    std::ofstream(dir / "scene.json") << coveredScene().dump();
    const std::string render = "render " + q(dir / "scene.json") + " --quiet --spp 2 ";
    std::string err;
    ASSERT_EQ(test::runPenumbra(render + "--aov depth,shape_id -o " + q(dir / "a.exr"), &err), 0) << err;
    ASSERT_EQ(
        test::runPenumbra(render + "--aov depth,shape_id --set sampler.sample_offset=2 -o " + q(dir / "b.exr"), &err),
        0)
        << err;
    ASSERT_EQ(test::runPenumbra(render + "--aov depth --set sampler.sample_offset=4 -o " + q(dir / "c.exr"), &err), 0)
        << err;
    // A partial whose ids differ at one pixel (as another scene's would).
    Image b = readExr(dir / "b.exr");
    b.aovs[1].ids[5] += 1;
    writeExr(dir / "b-other.exr", b);

    EXPECT_EQ(test::runPenumbra("merge " + q(dir / "a.exr") + " " + q(dir / "c.exr") + " -o " + q(dir / "m.exr"), &err),
              2);
    EXPECT_NE(err.find((dir / "c.exr").string() + ": AOVs depth differ from"), std::string::npos) << err;
    EXPECT_EQ(err.find('\n'), err.size() - 1) << err;
    EXPECT_EQ(
        test::runPenumbra("merge " + q(dir / "a.exr") + " " + q(dir / "b-other.exr") + " -o " + q(dir / "m.exr"), &err),
        2);
    EXPECT_NE(err.find((dir / "b-other.exr").string() + ": shape_id at pixel (5, 0) is"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "m.exr"));
    ASSERT_EQ(test::runPenumbra("merge " + q(dir / "a.exr") + " " + q(dir / "b.exr") + " -o " + q(dir / "m.exr"), &err),
              0)
        << err;
}

// Depth where some pieces saw no hit: the spp-weighted mean of the pieces that did.
TEST(MergeAovs, DepthAveragesThePiecesThatHit) {
    auto depth = [](float d) { return floats("depth", {"depth.Z"}, {d}); };
    const float inf = std::numeric_limits<float>::infinity();
    const Image merged =
        mergeImages({test::onePixelPartial(0, 2, 1, {depth(4)}), test::onePixelPartial(2, 6, 1, {depth(inf)}),
                     test::onePixelPartial(8, 1, 1, {depth(7)})},
                    {"a", "b", "c"});
    EXPECT_FLOAT_EQ(merged.aovs[0].floats[0], (2 * 4 + 1 * 7) / 3.0f);
    const Image none = mergeImages(
        {test::onePixelPartial(0, 2, 1, {depth(inf)}), test::onePixelPartial(2, 6, 1, {depth(inf)})}, {"a", "b"});
    EXPECT_EQ(none.aovs[0].floats[0], inf);
    try {
        mergeImages({test::onePixelPartial(0, 2, 1, {depth(4)}), test::onePixelPartial(2, 6, 1, {depth(-1)})},
                    {"a", "b"});
        ADD_FAILURE() << "negative depth merged";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("b: depth at pixel (0, 0) is negative"), std::string::npos) << e.what();
    }
}

// The variance of pieces of samples {1, 3} and {2, 6, 4} pooled is that of one render of
// {1, 3, 2, 6, 4}: mean 3.2, s^2 = (sum x^2 - 5 * 3.2^2) / 4 = 3.7, estimate s^2 / 5 = 0.74.
// Each piece: mean 2, s^2 2, estimate 1; mean 4, s^2 4, estimate 4 / 3.
TEST(MergeAovs, VarianceIsTheOneRendersEstimate) {
    auto variance = [](float v) { return floats("variance", {"variance.R", "variance.G", "variance.B"}, {v, v, v}); };
    const Image merged = mergeImages(
        {test::onePixelPartial(0, 2, 2, {variance(1)}), test::onePixelPartial(2, 3, 4, {variance(4.0f / 3)})},
        {"a", "b"});
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(merged.aovs[0].floats[c], 0.74, 1e-6);
    // Pieces of one sample hold no estimate each (0), yet together they do: {1, 3} -> s^2 / 2 = 1.
    const Image ones = mergeImages(
        {test::onePixelPartial(0, 1, 1, {variance(0)}), test::onePixelPartial(1, 1, 3, {variance(0)})}, {"a", "b"});
    EXPECT_NEAR(ones.aovs[0].floats[0], 1.0, 1e-6);
}
