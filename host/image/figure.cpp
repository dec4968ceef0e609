// Figure compositing and label text. stb_easy_font emits each glyph as axis-aligned quads
// in font pixels (y down); they are filled here at integer scale, with no antialiasing.
#include "image/figure.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

namespace penumbra {
namespace {

// stb_easy_font indexes its glyph table with (c - 32): keep to printable ASCII.
std::string printable(const std::string& text) {
    std::string out = text;
    for (char& c : out)
        if (c < 32 || c > 126) c = '?';
    return out;
}

// Font pixels from the top of a line to the bottom of its descenders (g, p, y reach row 9).
constexpr int kTextHeight = 10;
constexpr int kLabelScale = 2;
constexpr int kLabelPadding = 6;

}  // namespace

int textWidth(const std::string& text) {
    std::string s = printable(text);
    return stb_easy_font_width(s.data());
}

void drawText(Rgb8Image& image, int x, int y, const std::string& text, int scale, const uint8_t rgb[3], int clipX0,
              int clipY0, int clipX1, int clipY1) {
    std::string s = printable(text);
    // About 270 bytes per character (the header's estimate); 64 bytes per quad.
    std::vector<char> vertices(std::max<size_t>(1, s.size()) * 400);
    const int quads = stb_easy_font_print(0, 0, s.data(), nullptr, vertices.data(), int(vertices.size()));
    clipX0 = std::max(clipX0, 0);
    clipY0 = std::max(clipY0, 0);
    clipX1 = std::min(clipX1, int(image.width));
    clipY1 = std::min(clipY1, int(image.height));
    for (int q = 0; q < quads; ++q) {
        // Vertex layout: x, y, z as float, then 4 bytes of colour: 16 bytes, 4 per quad.
        float qx0 = 1e30f, qy0 = 1e30f, qx1 = -1e30f, qy1 = -1e30f;
        for (int v = 0; v < 4; ++v) {
            const float* p = reinterpret_cast<const float*>(vertices.data() + (q * 4 + v) * 16);
            qx0 = std::min(qx0, p[0]);
            qx1 = std::max(qx1, p[0]);
            qy0 = std::min(qy0, p[1]);
            qy1 = std::max(qy1, p[1]);
        }
        // Fill the pixels whose centres lie inside the scaled quad.
        const int px0 = std::max(clipX0, x + int(qx0 * scale)), px1 = std::min(clipX1, x + int(qx1 * scale));
        const int py0 = std::max(clipY0, y + int(qy0 * scale)), py1 = std::min(clipY1, y + int(qy1 * scale));
        for (int py = py0; py < py1; ++py)
            for (int px = px0; px < px1; ++px) {
                uint8_t* d = &image.rgb[(size_t(py) * image.width + px) * 3];
                d[0] = rgb[0];
                d[1] = rgb[1];
                d[2] = rgb[2];
            }
    }
}

void figureSize(uint32_t count, uint32_t columns, uint32_t panelWidth, uint32_t panelHeight, uint32_t& width,
                uint32_t& height) {
    columns = std::max(1u, std::min(columns, count));
    const uint32_t rows = (count + columns - 1) / columns;
    width = columns * panelWidth + (columns + 1) * kFigureGap;
    height = rows * (kFigureLabelHeight + panelHeight) + (rows + 1) * kFigureGap;
}

Rgb8Image composeFigure(const std::vector<FigurePanel>& panels, uint32_t columns, float exposure) {
    if (panels.empty()) throw std::invalid_argument("composeFigure: no panels");
    const uint32_t pw = panels[0].image->width, ph = panels[0].image->height;
    for (const FigurePanel& p : panels)
        if (p.image->width != pw || p.image->height != ph || p.image->rgb.size() != size_t(pw) * ph * 3)
            throw std::invalid_argument("composeFigure: panel \"" + p.label + "\" is " + std::to_string(p.image->width) +
                                        "x" + std::to_string(p.image->height) + ", the first is " +
                                        std::to_string(pw) + "x" + std::to_string(ph));
    columns = std::max(1u, std::min(columns, uint32_t(panels.size())));
    Rgb8Image figure;
    figureSize(uint32_t(panels.size()), columns, pw, ph, figure.width, figure.height);
    figure.rgb.assign(size_t(figure.width) * figure.height * 3, kFigureBackground);

    const float scale = std::exp2(exposure);
    const uint8_t white[3] = {255, 255, 255};
    for (size_t i = 0; i < panels.size(); ++i) {
        const int cellX = int(kFigureGap + (i % columns) * (pw + kFigureGap));
        const int cellY = int(kFigureGap + (i / columns) * (kFigureLabelHeight + ph + kFigureGap));
        const int panelY = cellY + int(kFigureLabelHeight);
        for (uint32_t y = 0; y < ph; ++y)
            for (uint32_t x = 0; x < pw; ++x) {
                const float* src = panels[i].image->pixel(x, y);
                uint8_t* dst = &figure.rgb[(size_t(panelY + int(y)) * figure.width + cellX + x) * 3];
                for (int c = 0; c < 3; ++c) dst[c] = linearToSrgb8(src[c] * scale);
            }
        // 2x when the label fits the panel's width, else 1x, clipped to the strip either way.
        const int room = int(pw) - 2 * kLabelPadding;
        const int textScale = textWidth(panels[i].label) * kLabelScale <= room ? kLabelScale : 1;
        const int textY = cellY + (int(kFigureLabelHeight) - kTextHeight * textScale) / 2;
        drawText(figure, cellX + std::min(kLabelPadding, int(pw) / 8), textY, panels[i].label, textScale, white, cellX,
                 cellY, cellX + int(pw), panelY);
    }
    return figure;
}

}  // namespace penumbra
