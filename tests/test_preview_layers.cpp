// The preview's layer key (preview/layer_cycle.h, docs/guide/preview.md) without a window:
// L steps rgb -> each of film.aovs -> rgb, a scene without AOVs stays on rgb, and a layer
// becomes the tone map's RGBA8 pixels through the sRGB encoding of its false colours.
#include <gtest/gtest.h>

#include "image/aov_false_color.h"
#include "preview/key_bindings.h"
#include "preview/layer_cycle.h"

using namespace penumbra;
using namespace penumbra::preview;

TEST(PreviewLayers, TheKeyCyclesRgbThenEachAovThenRgb) {
    EXPECT_EQ(actionForKeyName("a"), Action::CycleLayer);
    EXPECT_NE(keyHelp().find("\n  L "), std::string::npos) << keyHelp();
    LayerCycle layers({"depth", "normal", "shape_id"});
    std::vector<std::string> seen{layers.name()};
    for (int i = 0; i < 5; ++i) {
        EXPECT_TRUE(layers.next());
        seen.push_back(layers.name());
    }
    EXPECT_EQ(seen, (std::vector<std::string>{"rgb", "depth", "normal", "shape_id", "rgb", "depth"}));

    LayerCycle none({});
    EXPECT_FALSE(none.next());
    EXPECT_TRUE(none.showsRgb());
    EXPECT_EQ(none.name(), "rgb");
}

TEST(PreviewLayers, LayerPixelsArePackedLikeTheToneMapsWithoutExposure) {
    Image image;
    image.width = 2;
    image.height = 1;
    image.rgb = {100, 100, 100, 0, 0, 0};  // radiance plays no part
    image.aovs.push_back({"normal", {"normal.X", "normal.Y", "normal.Z"}, {0, 0, 1, -1, 0, 0}, {}});
    image.aovs.push_back({"shape_id", {"shape_id"}, {}, {3, 4294967295u}});
    // R | G << 8 | B << 16 | 255 << 24 of n * 0.5 + 0.5: (128, 128, 255) and (0, 128, 128).
    EXPECT_EQ(layerPixels(image, "normal"), (std::vector<uint32_t>{0xffff8080u, 0xff808000u}));
    const std::vector<uint32_t> ids = layerPixels(image, "shape_id");
    const std::vector<float> colour = aovFalseColor(image.aovs[1], 2);
    EXPECT_EQ(ids[0], uint32_t(linearToSrgb8(colour[0])) | uint32_t(linearToSrgb8(colour[1])) << 8 |
                          uint32_t(linearToSrgb8(colour[2])) << 16 | 0xff000000u);
    EXPECT_EQ(ids[1], 0xff000000u);  // a miss is black
    EXPECT_THROW(layerPixels(image, "depth"), std::logic_error);
}
