// How AOV layers are shown (image/aov_false_color.h): through the sRGB encoding that a PNG
// or the preview applies, normals are n * 0.5 + 0.5, depth runs from white (nearest) to
// black (farthest, and misses), ids are hashed colours, misses black.
#include <cmath>
#include <limits>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "image/aov_false_color.h"
#include "image/image.h"
#include "image/image_file.h"

using namespace penumbra;

namespace {

// The 8-bit code a PNG gets for a linear value (exposure 0, clamp).
int code(float linear) { return linearToSrgb8(linear); }

}  // namespace

TEST(AovFalseColor, SrgbDecodeInvertsTheEncodeAtEveryCode) {
    for (int c = 0; c < 256; ++c) EXPECT_EQ(code(srgbToLinear(float(c) / 255.0f)), c) << c;
}

TEST(AovFalseColor, NormalsShowAsHalfPlusHalf) {
    const AovLayer normal{"normal", {"normal.X", "normal.Y", "normal.Z"}, {0, 0, 1, -1, 0.5f, 0, 0, 0, 0}, {}};
    const std::vector<float> rgb = aovFalseColor(normal, 3);
    const int expected[9] = {128, 128, 255, 0, 191, 128, 128, 128, 128};  // round(255 (n / 2 + 1 / 2))
    for (int k = 0; k < 9; ++k) EXPECT_EQ(code(rgb[k]), expected[k]) << k;
}

TEST(AovFalseColor, DepthIsNormalizedNearestWhiteMissesBlack) {
    const float inf = std::numeric_limits<float>::infinity();
    const AovLayer depth{"depth", {"depth.Z"}, {2, 6, 4, inf}, {}};
    const std::vector<float> rgb = aovFalseColor(depth, 4);
    const int expected[4] = {255, 0, 128, 0};
    for (int p = 0; p < 4; ++p)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(code(rgb[3 * p + c]), expected[p]) << p;
}

TEST(AovFalseColor, IdsAreStableDistinctColoursAndMissesBlack) {
    AovLayer ids{"shape_id", {"shape_id"}, {}, {}};
    for (uint32_t id = 0; id < 64; ++id) ids.ids.push_back(id);
    ids.ids.push_back(4294967295u);
    ids.ids.push_back(7);
    const std::vector<float> rgb = aovFalseColor(ids, ids.ids.size());
    std::set<std::tuple<int, int, int>> colours;
    for (size_t p = 0; p < 64; ++p) {
        colours.insert({code(rgb[3 * p]), code(rgb[3 * p + 1]), code(rgb[3 * p + 2])});
        for (int c = 0; c < 3; ++c) EXPECT_GE(code(rgb[3 * p + c]), 63) << "id " << p << " as dark as a miss";
    }
    EXPECT_EQ(colours.size(), 64u);  // neighbouring ids, different colours
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(rgb[3 * 64 + c], 0.0f);            // the miss
        EXPECT_EQ(rgb[3 * 65 + c], rgb[3 * 7 + c]);  // the same id, the same colour
    }
}
