// Bounded-time scheduling of render passes (see pass_bands.h).
#include "render/pass_bands.h"

#include <algorithm>
#include <cmath>
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
    const bool passStart =
        std::all_of(m_strips.begin(), m_strips.end(), [](const Strip& s) { return s.row == 0 && s.column == 0; });
    // Sweeps of row bands, once every strip is measured and a row of one sample takes at
    // most half the target (pass_bands.h).
    const bool sweepsFit = passStart && allMeasured() && maxCost() * m_width <= target / 2 &&
                           (m_maxPixelSamples == 0 || m_maxPixelSamples >= m_width);
    if (m_sweepCount > 0 || sweepsFit) return nextSweepBand(target);
    // Sized by the costliest strip's last measured cost per pixel sample, growing at most x2
    // per band: a part of the film costlier than any measured takes at most twice the last
    // band's pixels.
    double pixels = double(m_firstBandPixels);
    if (m_last.pixelSamples() > 0) pixels = 2.0 * double(m_last.pixelSamples());
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
    m_last = band;
    m_lastInSweep = false;
    m_pixelSamplesDone += band.pixelSamples();
    if (std::all_of(m_strips.begin(), m_strips.end(), [](const Strip& t) { return t.done(); })) {
        ++m_sample;
        for (Strip& t : m_strips) t.row = t.column = 0;
        m_nextStrip = 0;
    }
    return band;
}

PassBand PassBands::nextSweepBand(double target) {
    const double rowSeconds = std::max(maxCost(), 0.0) * m_width;  // the costliest row, one sample
    if (m_sweepCount == 0) {
        // As many samples as one row takes within the target (and as fit in the cap on a
        // band's pixel samples, a whole row each): the more samples a dispatch adds to each
        // pixel, the faster each one is (pass_bands.h).
        double count = rowSeconds > 0.0 ? target / rowSeconds : double(kMaxPassesPerBand);
        count = std::min({count, double(kMaxPassesPerBand), double(m_spp - m_sample)});
        if (m_maxPixelSamples > 0) count = std::min(count, std::floor(double(m_maxPixelSamples) / m_width));
        m_sweepCount = std::max<uint32_t>(1, uint32_t(count));
        m_sweepRow = 0;
    }
    // As many rows as fit in the target at the costliest strip's cost, and at most twice the
    // pixel samples of the last band or of one pass, whichever is more: the growth that
    // whole passes had (two passes after a split one, then twice the last band).
    const double rowSamples = double(m_width) * m_sweepCount;  // pixel samples of one row of the sweep
    const double pass = double(m_width) * m_height;
    double rows = rowSeconds > 0.0 ? target / (rowSeconds * m_sweepCount) : double(m_height);
    rows = std::min(rows, 2.0 * std::max(double(m_last.pixelSamples()), pass) / rowSamples);
    if (m_maxPixelSamples > 0) rows = std::min(rows, double(m_maxPixelSamples) / rowSamples);
    rows = std::clamp(rows, 1.0, double(m_height - m_sweepRow));
    PassBand band{m_sample, m_sweepCount, m_sweepRow, uint32_t(rows), 0, m_width};
    m_last = band;
    m_lastInSweep = true;
    m_sweepRow += band.rowCount;
    m_pixelSamplesDone += band.pixelSamples();
    if (m_sweepRow == m_height) {
        m_sample += m_sweepCount;
        m_sweepCount = 0;
        m_sweepRow = 0;
    }
    return band;
}

bool PassBands::allMeasured() const {
    return std::all_of(m_strips.begin(), m_strips.end(), [](const Strip& t) { return t.cost >= 0.0; });
}

double PassBands::maxCost() const {
    double cost = -1.0;
    for (const Strip& s : m_strips) cost = std::max(cost, s.cost);
    return cost;
}

void PassBands::measured(double seconds) {
    const uint64_t pixels = m_last.pixelSamples();
    if (pixels == 0) return;
    seconds = std::max(seconds, 0.0);
    m_fixedSeconds = m_fixedSeconds < 0.0 ? seconds : std::min(m_fixedSeconds, seconds);
    const double cost = std::max(seconds - m_fixedSeconds, 0.0) / double(pixels);
    if (!m_lastInSweep) {
        m_strips[size_t(m_lastStrip)].cost = cost;
        return;
    }
    // A sweep's band spans strips of different costs: its mean may only raise theirs, so
    // that a costly strip's estimate is never lowered by the cheap rows beside it.
    const uint32_t end = m_last.firstRow + m_last.rowCount;
    for (Strip& t : m_strips)
        if (t.firstRow < end && m_last.firstRow < t.firstRow + t.rows) t.cost = std::max(t.cost, cost);
}

}  // namespace penumbra
