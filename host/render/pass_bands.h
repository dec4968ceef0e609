// Splitting a render into GPU submissions of bounded time, so that a stop (Ctrl-C, Slurm)
// is honoured within a fraction of a second whatever the settings. The film is cut into
// up to 8 horizontal strips, visited in a spread-out order (0, 4, 2, 6, 1, 5, 3, 7); each
// submission renders one band of one strip (rows, or a run of 8-pixel tiles of one row),
// sized by the costliest strip's cost per pixel sample and at most twice the previous
// band, or whole passes once a pass is known to take at most half the target. A band's
// time has a fixed part (on lavapipe under load, tens of milliseconds per dispatch) that
// is taken out before costs are computed, bounded by the shortest band seen. Costs differ
// across the image (sky is far cheaper than a glossy floor under 65536 light samples): the
// spread order measures every part of the film within the first few submissions, and
// sizing by the costliest keeps a budget learnt on cheap pixels from being spent on
// costly ones. Every pixel still receives sample indices 0..spp-1 exactly once and in
// order, so the sums (and the image) are bit-identical to whole passes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra {

// `count` passes, sample indices [firstSample, firstSample + count), over the pixels of
// rows [firstRow, firstRow + rowCount) x columns [firstColumn, firstColumn + columnCount).
struct PassBand {
    uint32_t firstSample = 0;
    uint32_t count = 0;
    uint32_t firstRow = 0;
    uint32_t rowCount = 0;
    uint32_t firstColumn = 0;
    uint32_t columnCount = 0;

    uint64_t pixelSamples() const { return uint64_t(count) * rowCount * columnCount; }
};

class PassBands {
public:
    // The kernels' tile width: a run of columns starts at a multiple of it and spans a
    // multiple of it (or reaches the film's right edge), since a dispatch covers whole tiles.
    static constexpr uint32_t kTile = 8;
    static constexpr uint32_t kMaxPassesPerBand = 1024;

    // `maxPixelSamples` > 0 caps every band (tests use it to force small bands).
    // `firstBandPixels`: the pixel samples of the first band, before anything is measured
    // (Renderer derives it from the rays a pixel sample traces; a tile by default).
    PassBands(uint32_t width, uint32_t height, uint32_t spp, uint64_t maxPixelSamples = 0,
              uint64_t firstBandPixels = kTile);

    // The next band, meant to take about `targetSeconds`. Advances the schedule.
    PassBand next(double targetSeconds);
    // The time the band from the last next() took.
    void measured(double seconds);

    bool finished() const { return m_sample >= m_spp; }
    // Sample indices every pixel has.
    uint32_t samplesDone() const { return m_sample; }

private:
    struct Strip {
        uint32_t firstRow = 0, rows = 0;
        uint32_t row = 0, column = 0;  // the next pixel of the current pass, relative row
        double cost = -1.0;            // its last band's seconds per pixel sample; < 0 unknown
        bool done() const { return row >= rows; }
    };
    // The costliest strip's cost, or < 0 if none is known.
    double maxCost() const;

    uint32_t m_width, m_height, m_spp;
    uint64_t m_maxPixelSamples;
    uint64_t m_firstBandPixels;
    uint32_t m_sample = 0;
    std::vector<Strip> m_strips;
    std::vector<uint32_t> m_order;  // strip visiting order
    size_t m_nextStrip = 0;         // position in m_order
    double m_fixedSeconds = -1.0;   // the shortest band so far: a bound on each band's fixed cost
    double m_passCost = -1.0;       // one whole pass, once measured or known for every strip
    uint32_t m_lastPasses = 0;      // passes in the last whole-pass band
    uint64_t m_lastPixels = 0;      // pixel samples of the last band
    bool m_lastWhole = false;       // the last band was whole passes
    int m_lastStrip = -1;           // the last band's strip
};

}  // namespace penumbra
