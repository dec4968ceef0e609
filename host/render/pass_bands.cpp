// Bounded-time scheduling of render passes (see pass_bands.h).
#include "render/pass_bands.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {

PassBands::PassBands(uint32_t width, uint32_t height, uint32_t spp, uint64_t maxPixelSamples, uint64_t firstBandPixels,
                     uint32_t maxBands)
    : m_width(width),
      m_height(height),
      m_spp(spp),
      m_maxPixelSamples(maxPixelSamples),
      m_firstBandPixels(std::max<uint64_t>(firstBandPixels, kTile)),
      m_maxBands(std::clamp<uint32_t>(maxBands, 1, kMaxBandsPerSubmission)) {
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

std::vector<PassBand> PassBands::next(double target) {
    if (finished()) throw std::logic_error("pass bands: the render is finished");
    uint64_t lastPixels = 0;  // of the last submission; 0 before the first
    for (const Handed& h : m_handed) lastPixels += h.band.pixelSamples();
    m_handed.clear();
    const bool passStart =
        std::all_of(m_strips.begin(), m_strips.end(), [](const Strip& s) { return s.row == 0 && s.column == 0; });
    // Sweeps of row bands, once every strip is measured and a row of one sample takes at
    // most half the target (pass_bands.h): one band per submission.
    const bool sweepsFit = passStart && allMeasured() && maxCost() * m_width <= target / 2 &&
                           (m_maxPixelSamples == 0 || m_maxPixelSamples >= m_width);
    if (m_sweepCount > 0 || sweepsFit) {
        m_handed.push_back({nextSweepBand(target, lastPixels), -1});
    } else {
        // The submission's pixel samples: sized by the costliest strip's last measured cost
        // per pixel sample, growing at most x2 per submission, so that a part of the film
        // costlier than any measured takes at most twice the last submission's pixels.
        double pixels = double(m_firstBandPixels);
        if (lastPixels > 0) pixels = 2.0 * double(lastPixels);
        if (maxCost() > 0.0) pixels = std::min(pixels, target / maxCost());
        pixels = std::max(pixels, double(kTile));
        // The pass's rest too where it is at most half as much again (x3 growth instead of
        // x2) and fits in the target at the costliest gross cost measured: a small last
        // submission of the pass would pay a submission's fixed cost for little work.
        const double rest = double(passPixelsLeft());
        if (lastPixels > 0 && maxGrossCost() >= 0.0 && rest <= 1.5 * pixels && rest * maxGrossCost() <= target)
            pixels = std::max(pixels, rest);
        if (m_maxPixelSamples > 0) pixels = std::min(pixels, double(m_maxPixelSamples));
        uint64_t budget = uint64_t(std::min(pixels, 1e15));
        // Bands of this pass's strips in the spread order until the budget is spent; a
        // submission ends with its pass, since sweeps wait for the pass's measurements.
        // After its first band, a submission takes only whole rows: a band has a fixed
        // cost (a dispatch's, about 0.04-0.1 ms on lavapipe), which a run of a few tiles
        // would pay for little work.
        const uint32_t sample = m_sample;
        do {
            const PassBand band = nextStripBand(budget);
            budget -= std::min(budget, band.pixelSamples());
        } while (m_sample == sample && budget >= m_width && m_handed.size() < m_maxBands && nextStripStartsARow());
    }
    std::vector<PassBand> bands;
    for (const Handed& h : m_handed) {
        bands.push_back(h.band);
        m_pixelSamplesDone += h.band.pixelSamples();
    }
    return bands;
}

bool PassBands::nextStripStartsARow() const {
    for (size_t i = 0; i < m_order.size(); ++i) {
        const Strip& s = m_strips[m_order[(m_nextStrip + i) % m_order.size()]];
        if (!s.done()) return s.column == 0;
    }
    return false;
}

PassBand PassBands::nextStripBand(uint64_t budget) {
    // The next strip with work left in this pass, in the spread order.
    while (m_strips[m_order[m_nextStrip % m_order.size()]].done()) ++m_nextStrip;
    const int strip = int(m_order[m_nextStrip++ % m_order.size()]);
    Strip& s = m_strips[size_t(strip)];
    PassBand band{m_sample, 1, s.firstRow + s.row, 1, s.column, 0};
    if (s.column == 0 && budget >= m_width) {
        // The strip's rest too where the budget would leave at most a quarter of it (a
        // band of a row or two later would cost a dispatch for little work), unless a cap
        // on the pixel samples bounds the submission.
        const uint32_t rest = s.rows - s.row;
        band.rowCount = uint32_t(std::min<uint64_t>(budget / m_width, rest));
        if (m_maxPixelSamples == 0 && 4 * (rest - band.rowCount) <= rest) band.rowCount = rest;
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
    m_handed.push_back({band, strip});
    if (std::all_of(m_strips.begin(), m_strips.end(), [](const Strip& t) { return t.done(); })) {
        ++m_sample;
        for (Strip& t : m_strips) t.row = t.column = 0;
        m_nextStrip = 0;
    }
    return band;
}

PassBand PassBands::nextSweepBand(double target, uint64_t lastPixels) {
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
    // pixel samples of the last submission or of one pass, whichever is more: the growth
    // that whole passes had (two passes after a split one, then twice the last band).
    const double rowSamples = double(m_width) * m_sweepCount;  // pixel samples of one row of the sweep
    const double pass = double(m_width) * m_height;
    double rows = rowSeconds > 0.0 ? target / (rowSeconds * m_sweepCount) : double(m_height);
    // x4 where even that is predicted to take at most a quarter of the target, so that a
    // render of a few samples per pixel finishes its sweep in one submission.
    const double basis = std::max(double(lastPixels), pass);
    const double growth = 4.0 * basis * std::max(maxGrossCost(), 0.0) <= target / 4 ? 4.0 : 2.0;
    rows = std::min(rows, growth * basis / rowSamples);
    if (m_maxPixelSamples > 0) rows = std::min(rows, double(m_maxPixelSamples) / rowSamples);
    rows = std::clamp(rows, 1.0, double(m_height - m_sweepRow));
    PassBand band{m_sample, m_sweepCount, m_sweepRow, uint32_t(rows), 0, m_width};
    m_sweepRow += band.rowCount;
    if (m_sweepRow == m_height) {
        m_sample += m_sweepCount;
        m_sweepCount = 0;
        m_sweepRow = 0;
    }
    return band;
}

uint64_t PassBands::passPixelsLeft() const {
    uint64_t left = 0;
    for (const Strip& s : m_strips) left += uint64_t(s.rows - s.row) * m_width - s.column;
    return left;
}

double PassBands::maxOver(double Strip::*cost) const {
    double most = -1.0;
    for (const Strip& s : m_strips) most = std::max(most, s.*cost);
    return most;
}

bool PassBands::allMeasured() const {
    return std::all_of(m_strips.begin(), m_strips.end(), [](const Strip& t) { return t.cost >= 0.0; });
}

void PassBands::measured(const std::vector<double>& seconds) {
    if (seconds.size() != m_handed.size())
        throw std::logic_error("pass bands: one time per band of the last submission expected");
    // The shortest band bounds each band's fixed part (pass_bands.h); all of this
    // submission's bands count before any cost is computed.
    for (size_t i = 0; i < seconds.size(); ++i) {
        if (m_handed[i].band.pixelSamples() == 0) continue;
        const double t = std::max(seconds[i], 0.0);
        m_fixedSeconds = m_fixedSeconds < 0.0 ? t : std::min(m_fixedSeconds, t);
    }
    for (size_t i = 0; i < seconds.size(); ++i) {
        const PassBand& band = m_handed[i].band;
        const uint64_t pixels = band.pixelSamples();
        if (pixels == 0) continue;
        const double cost = std::max(std::max(seconds[i], 0.0) - m_fixedSeconds, 0.0) / double(pixels);
        const double grossCost = std::max(seconds[i], 0.0) / double(pixels);
        if (m_handed[i].strip >= 0) {
            m_strips[size_t(m_handed[i].strip)].cost = cost;
            m_strips[size_t(m_handed[i].strip)].grossCost = grossCost;
            continue;
        }
        // A sweep's band spans strips of different costs: its mean may only raise theirs, so
        // that a costly strip's estimate is never lowered by the cheap rows beside it.
        const uint32_t end = band.firstRow + band.rowCount;
        for (Strip& t : m_strips)
            if (t.firstRow < end && band.firstRow < t.firstRow + t.rows) {
                t.cost = std::max(t.cost, cost);
                t.grossCost = std::max(t.grossCost, grossCost);
            }
    }
}

}  // namespace penumbra
