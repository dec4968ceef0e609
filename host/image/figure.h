// Comparison figures: renders composited side by side (or in a grid) into one 8-bit sRGB
// image, each under a label strip with text drawn from stb_easy_font's quads. Rendering the
// panels and writing the PNG are left to the caller (tools/figures/penumbra_figure.cpp, writePngRgb8).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "image/image.h"

namespace penumbra {

// 8-bit sRGB pixels, width * height * 3, row-major, top row first (what writePngRgb8 takes).
struct Rgb8Image {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<uint8_t> rgb;
};

struct FigurePanel {
    const Image* image = nullptr;  // linear radiance; every panel of a figure has the same size
    std::string label;             // printable ASCII; anything else is drawn as '?'
};

// The layout, in pixels: every cell is a label strip of kFigureLabelHeight above its panel,
// and kFigureGap of background separates the cells from each other and from the border.
inline constexpr uint32_t kFigureLabelHeight = 32;  // fits stb_easy_font's 12 px line at 2x
inline constexpr uint32_t kFigureGap = 4;
inline constexpr uint8_t kFigureBackground = 48;  // dark grey (sRGB code value) behind the text

// The size of a figure of `count` panels of panelWidth x panelHeight in `columns` columns
// (fewer when count is smaller; the last row may be partly empty).
void figureSize(uint32_t count, uint32_t columns, uint32_t panelWidth, uint32_t panelHeight, uint32_t& width,
                uint32_t& height);

// Composites the panels (radiance times 2^exposure, clamped, sRGB-encoded as writePng does)
// row by row, `columns` per row, each under its label. Throws std::invalid_argument when
// there are no panels or their sizes differ.
Rgb8Image composeFigure(const std::vector<FigurePanel>& panels, uint32_t columns, float exposure = 0.0f);

// Draws `text` with its top-left corner at (x, y), each font pixel as a scale x scale block,
// in `rgb`, clipped to the rectangle [clipX0, clipX1) x [clipY0, clipY1) and to the image.
void drawText(Rgb8Image& image, int x, int y, const std::string& text, int scale, const uint8_t rgb[3], int clipX0,
              int clipY0, int clipX1, int clipY1);
// The width of `text` in font pixels at scale 1 (a line is 12 font pixels high, the
// font's own line advance; descenders stay inside it).
int textWidth(const std::string& text);

}  // namespace penumbra
