// penumbra_figure from the outside (exit status, the stdout table, the PNG's layout, bad
// input) and the compositing it relies on (host/image/figure.h). The renders are tiny: the
// numbers are only checked to be finite and non-negative, not for which strategy wins.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "image/figure.h"
#include "image/image.h"
#include "render_helpers.h"

#include "png_reader.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// A glossy floor under a sphere light and a small quad light: every strategy and sphere
// sampling converges to the same image, with different noise.
json figureScene() {
    return {
        {"camera", {{"eye", {0, 2, 4}}, {"target", {0, 0, 0}}, {"fov_y", 45}}},
        {"film", {{"width", 32}, {"height", 24}}},
        {"sampler", {{"spp", 4}}},
        {"integrator", {{"type", "direct"}}},
        {"materials", {{"glossy", {{"type", "phong"}, {"kd", {0.3, 0.3, 0.3}}, {"ks", {0.5, 0.5, 0.5}}, {"exponent", 50}}}}},
        {"shapes",
         {{{"type", "quad"}, {"origin", {-3, 0, -3}}, {"edge_u", {0, 0, 6}}, {"edge_v", {6, 0, 0}}, {"material", "glossy"}},
          {{"type", "sphere"}, {"center", {-0.8, 1, -0.5}}, {"radius", 0.3}, {"power", {40, 40, 40}}},
          {{"type", "quad"}, {"origin", {0.6, 1.2, 0}}, {"edge_u", {0.3, 0, 0}}, {"edge_v", {0, 0, 0.3}},
           {"emission", {20, 20, 20}}, {"two_sided", true}}}},
    };
}

fs::path writeScene(const std::string& name) {
    fs::path path = test::outputPath(name);
    std::ofstream(path) << figureScene().dump(2);
    return path;
}

// 'PATH', shell-quoted (by append: GCC 12 warns falsely about "'" + std::string&&).
std::string quoted(const fs::path& path) { return std::string("'").append(path.string()).append("'"); }

int runFigure(const std::string& args, std::string* err, std::string* out = nullptr) {
    return test::runProgram(PENUMBRA_FIGURE_EXECUTABLE, args, err, out);
}

using test::Png;
using test::readPng;

// Parses `VALUE relmse X rmse Y seconds Z` lines; fails the test on any other line.
std::vector<std::pair<std::string, double>> parseTable(const std::string& out) {
    std::vector<std::pair<std::string, double>> rows;
    std::istringstream lines(out);
    std::string line;
    while (std::getline(lines, line)) {
        std::istringstream fields(line);
        std::string value, k1, k2, k3;
        double relmse = NAN, rmse = NAN, seconds = NAN;
        fields >> value >> k1 >> relmse >> k2 >> rmse >> k3 >> seconds;
        EXPECT_TRUE(fields && k1 == "relmse" && k2 == "rmse" && k3 == "seconds") << "bad line: " << line;
        EXPECT_TRUE(std::isfinite(relmse) && relmse >= 0) << line;
        EXPECT_TRUE(std::isfinite(rmse) && rmse >= 0) << line;
        EXPECT_TRUE(std::isfinite(seconds) && seconds >= 0) << line;
        rows.push_back({value, relmse});
    }
    return rows;
}

void expectOneLine(const std::string& err) {
    ASSERT_FALSE(err.empty());
    EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line: " << err;
}

}  // namespace

TEST(Figure, ComposeFigureLaysOutPanelsUnderLabels) {
    Image a{4, 3, std::vector<float>(4 * 3 * 3, 0.25f), {}}, b{4, 3, std::vector<float>(4 * 3 * 3, 1.0f), {}};
    Rgb8Image f = composeFigure({{&a, "A"}, {&b, "B"}, {&a, "C"}}, 2);
    uint32_t w = 0, h = 0;
    figureSize(3, 2, 4, 3, w, h);
    EXPECT_EQ(f.width, w);
    EXPECT_EQ(f.height, h);
    EXPECT_EQ(w, 2 * 4 + 3 * kFigureGap);
    EXPECT_EQ(h, 2 * (kFigureLabelHeight + 3) + 3 * kFigureGap);
    auto at = [&](uint32_t x, uint32_t y) { return f.rgb[(size_t(y) * f.width + x) * 3]; };
    // Panel pixels are sRGB-encoded radiance; the second panel is right of the first.
    EXPECT_EQ(at(kFigureGap, kFigureGap + kFigureLabelHeight), linearToSrgb8(0.25f));
    EXPECT_EQ(at(2 * kFigureGap + 4, kFigureGap + kFigureLabelHeight + 2), 255);
    // The third panel starts the second row; the empty fourth cell is background.
    const uint32_t row2 = 2 * kFigureGap + kFigureLabelHeight + 3;
    EXPECT_EQ(at(kFigureGap + 3, row2 + kFigureLabelHeight), linearToSrgb8(0.25f));
    EXPECT_EQ(at(2 * kFigureGap + 4, row2 + kFigureLabelHeight), kFigureBackground);

    // A label that fits is drawn at 2x in white on the strip, and nowhere else.
    Image wide{400, 10, std::vector<float>(400 * 10 * 3, 0.0f), {}};
    Rgb8Image g = composeFigure({{&wide, "mis  16 spp  relMSE 0.0123"}}, 1);
    int white = 0, whiteOutsideStrip = 0;
    for (uint32_t y = 0; y < g.height; ++y)
        for (uint32_t x = 0; x < g.width; ++x) {
            const uint8_t* p = &g.rgb[(size_t(y) * g.width + x) * 3];
            if (p[0] == 255 && p[1] == 255 && p[2] == 255) {
                ++white;
                if (y < kFigureGap || y >= kFigureGap + kFigureLabelHeight) ++whiteOutsideStrip;
            }
        }
    EXPECT_GT(white, 4 * textWidth("mis  16 spp  relMSE 0.0123")) << "label missing or not scaled 2x";
    EXPECT_EQ(whiteOutsideStrip, 0);
}

TEST(Figure, VaryStrategyPrintsTableAndWritesOneLabelledPng) {
    fs::path scene = writeScene("figure-scene.json");
    fs::path png = test::outputPath("figure-strategy.png");
    fs::path exr = test::outputPath("figure-strategy-");
    fs::remove(png);
    std::string err, out;
    int status = runFigure(quoted(scene) + " --vary strategy --spp 4 --reference-spp 32 --exr-prefix " + quoted(exr) +
                               " -o " + quoted(png) + " --quiet",
                           &err, &out);
    ASSERT_EQ(status, 0) << err;
    auto rows = parseTable(out);
    // Every value of the option, in the order the format lists them, one panel each in one row.
    const std::vector<std::string> expected = {"light", "bsdf", "mis", "mixture", "ris"};
    const int n = int(expected.size());
    ASSERT_EQ(rows.size(), expected.size()) << out;
    for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(rows[i].first, expected[i]);

    Png image = readPng(png);
    uint32_t w = 0, h = 0;
    figureSize(n, n, 32, 24, w, h);
    EXPECT_EQ(w, n * 32 + (n + 1) * kFigureGap);
    EXPECT_EQ(h, kFigureLabelHeight + 24 + 2 * kFigureGap);
    ASSERT_EQ(image.width, int(w)) << png;
    ASSERT_EQ(image.height, int(h)) << png;
    // Each label strip has text in it (white), each panel the lit floor (not background).
    for (int i = 0; i < n; ++i) {
        const int x0 = int(kFigureGap) + i * (32 + int(kFigureGap));
        int white = 0;
        for (int y = int(kFigureGap); y < int(kFigureGap + kFigureLabelHeight); ++y)
            for (int x = x0; x < x0 + 32; ++x) white += image.pixels[(size_t(y) * w + x) * 3] == 255;
        EXPECT_GT(white, 10) << "no label over panel " << i;
    }

    // The panels' EXRs carry their spp; the reference its own spp and seed.
    Image mis = readExr(exr.string() + "mis.exr");
    Image reference = readExr(exr.string() + "reference.exr");
    EXPECT_EQ(mis.meta.spp, 4);
    EXPECT_EQ(reference.meta.spp, 32);
    EXPECT_NE(reference.meta.seed, mis.meta.seed);
}

TEST(Figure, ValuesAndColumnsMakeAGrid) {
    fs::path scene = writeScene("figure-grid-scene.json");
    fs::path png = test::outputPath("figure-grid.png");
    fs::remove(png);
    std::string err, out;
    int status = runFigure(quoted(scene) +
                               " --vary sphere_sampling --values cap,area,solid_angle --columns 2 --spp 2 "
                               "--reference-spp 8 --width 24 --height 16 --set integrator.strategy=light -o " +
                               quoted(png),
                           &err, &out);
    ASSERT_EQ(status, 0) << err;
    auto rows = parseTable(out);
    ASSERT_EQ(rows.size(), 3u) << out;
    EXPECT_EQ(rows[0].first, "cap");
    Png image = readPng(png);
    EXPECT_EQ(image.width, int(2 * 24 + 3 * kFigureGap));
    EXPECT_EQ(image.height, int(2 * (kFigureLabelHeight + 16) + 3 * kFigureGap));
}

TEST(Figure, BadInputExitsTwoWithOneLineAndWritesNothing) {
    fs::path scene = writeScene("figure-bad-scene.json");
    fs::path png = test::outputPath("figure-bad.png");
    fs::remove(png);
    std::string err;

    EXPECT_EQ(runFigure(quoted(scene) + " --vary colour -o " + quoted(png), &err), 2) << err;
    expectOneLine(err);
    EXPECT_NE(err.find("colour"), std::string::npos) << err;

    EXPECT_EQ(runFigure(quoted(scene) + " --vary strategy --values mis,best -o " + quoted(png), &err),
              2)
        << err;
    expectOneLine(err);
    EXPECT_NE(err.find("best"), std::string::npos) << err;

    EXPECT_EQ(runFigure("/nonexistent/scene.json --vary strategy -o " + quoted(png), &err), 2) << err;
    expectOneLine(err);
    EXPECT_NE(err.find("scene.json"), std::string::npos) << err;

    EXPECT_EQ(runFigure(quoted(scene) + " --vary strategy --spp zero -o " + quoted(png), &err), 2)
        << err;
    expectOneLine(err);

    EXPECT_EQ(runFigure("", &err), 2) << err;
    expectOneLine(err);
    EXPECT_FALSE(fs::exists(png));
}
