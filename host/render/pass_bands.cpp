// Bounded-time scheduling of render passes (see pass_bands.h).
#include "render/pass_bands.h"

#include <algorithm>
#include <stdexcept>

namespace penumbra {

PassBands::PassBands(uint32_t width, uint32_t height, uint32_t spp, uint64_t maxPixelSamples, uint64_t firstBandPixels)
    : m_width(width),
      m_height(height),
      m_spp(spp),
      m_maxPixelSamples(maxPixelSamples),
      m_firstBandPixels(std::max<uint64_t>(firstBandPixels, kTile)) {
    if (width == 0 || height == 0) throw std::invalid_argument("pass bands: the film has no pixels");
    const uint32_t count = std::min<uint32_t>(8, height);
    for (uint32_t i = 0; i < count; ++i) {
        Strip s;
        s.firstRow = uint32_t(uint64_t(height) * i / count);
        s.rows = uint32_t(uint64_t(height) * (i + 1) / count) - s.firstRow;
        m_strips.push_back(s);
    }
    // Bit-reversed order over 8: every prefix is spread over the film.
    for (uint32_t i : {0u, 4u, 2u, 6u, 1u, 5u, 3u, 7u})
        if (i < count) m_order.push_back(i);
}

PassBand PassBands::next(double target) {
    if (finished()) throw std::logic_error("pass bands: the render is finished");
    const uint64_t pass = uint64_t(m_width) * m_height;
    const bool passStart =
        std::all_of(m_strips.begin(), m_strips.end(), [](const Strip& s) { return s.row == 0 && s.column == 0; });
    // Whole passes, once one is known to take at most half the target.
    if (passStart && m_passCost >= 0.0 && m_passCost <= target / 2 &&
        (m_maxPixelSamples == 0 || m_maxPixelSamples >= pass)) {
        double passes = m_passCost > 0.0 ? target / m_passCost : double(kMaxPassesPerBand);
        passes = std::min(
            {passes, 2.0 * std::max<uint32_t>(m_lastPasses, 1), double(kMaxPassesPerBand), double(m_spp - m_sample)});
        // Whole passes that fit in the per-pixel sample budget (integer division: a
        // partial pass does not count).
        const uint32_t passesThatFit = m_maxPixelSamples / pass;
        if (m_maxPixelSamples > 0) passes = std::min(passes, double(passesThatFit));
        const uint32_t count = std::max<uint32_t>(1, uint32_t(passes));
        PassBand band{m_sample, count, 0, m_height, 0, m_width};
        m_sample += count;
        m_lastPasses = count;
        m_lastPixels = band.pixelSamples();
        m_lastWhole = true;
        return band;
    }
    // Sized by the costliest strip's last measured cost per pixel sample, growing at most x2
    // per band: a part of the film costlier than any measured takes at most twice the last
    // band's pixels.
    double pixels = double(m_firstBandPixels);
    if (m_lastPixels > 0) pixels = 2.0 * double(m_lastPixels);
    if (maxCost() > 0.0) pixels = std::min(pixels, target / maxCost());
    pixels = std::max(pixels, double(kTile));
    if (m_maxPixelSamples > 0) pixels = std::min(pixels, double(m_maxPixelSamples));
    const uint64_t budget = uint64_t(std::min(pixels, 1e15));

    // The next strip with work left in this pass, in the spread order.
    while (m_strips[m_order[m_nextStrip % m_order.size()]].done()) ++m_nextStrip;
    m_lastStrip = int(m_order[m_nextStrip++ % m_order.size()]);
    Strip& s = m_strips[size_t(m_lastStrip)];
    PassBand band{m_sample, 1, s.firstRow + s.row, 1, s.column, 0};
    if (s.column == 0 && budget >= m_width) {
        band.rowCount = uint32_t(std::min<uint64_t>(budget / m_width, s.rows - s.row));
        band.columnCount = m_width;
        s.row += band.rowCount;
    } else {
        const uint64_t columns = std::max<uint64_t>(budget / kTile * kTile, kTile);
        band.columnCount = uint32_t(std::min<uint64_t>(columns, m_width - s.column));
        s.column += band.columnCount;
        if (s.column == m_width) {
            s.column = 0;
            ++s.row;
        }
    }
    m_lastPixels = band.pixelSamples();
    m_lastWhole = false;
    if (std::all_of(m_strips.begin(), m_strips.end(), [](const Strip& t) { return t.done(); })) {
        ++m_sample;
        for (Strip& t : m_strips) t.row = t.column = 0;
        m_nextStrip = 0;
    }
    return band;
}

double PassBands::maxCost() const {
    double cost = -1.0;
    for (const Strip& s : m_strips) cost = std::max(cost, s.cost);
    return cost;
}

void PassBands::measured(double seconds) {
    if (m_lastPixels == 0) return;
    seconds = std::max(seconds, 0.0);
    m_fixedSeconds = m_fixedSeconds < 0.0 ? seconds : std::min(m_fixedSeconds, seconds);
    if (m_lastWhole) {
        m_passCost = seconds / m_lastPasses;
        return;
    }
    Strip& s = m_strips[size_t(m_lastStrip)];
    s.cost = std::max(seconds - m_fixedSeconds, 0.0) / double(m_lastPixels);
    // A whole pass: every strip's cost over its pixels, plus one band's fixed cost.
    if (std::all_of(m_strips.begin(), m_strips.end(), [](const Strip& t) { return t.cost >= 0.0; })) {
        double pass = m_fixedSeconds;
        for (const Strip& t : m_strips) pass += t.cost * double(t.rows) * m_width;
        m_passCost = pass;
    }
}

}  // namespace penumbra
