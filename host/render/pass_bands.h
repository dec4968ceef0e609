// Splitting a render into GPU submissions of bounded time, so that a stop (Ctrl-C, Slurm)
// is honoured within a fraction of a second whatever the settings. The film is cut into
// up to 8 horizontal strips, visited in a spread-out order (0, 4, 2, 6, 1, 5, 3, 7); each
// submission renders one band of one strip (rows, or a run of 8-pixel tiles of one row),
// sized by the costliest strip's cost per pixel sample and at most twice the previous
// band, or sweeps of row bands (below) once every strip is measured. A band's
// time has a fixed part (on lavapipe under load, tens of milliseconds per dispatch) that
// is taken out before costs are computed, bounded by the shortest band seen. Costs differ
// across the image (sky is far cheaper than a glossy floor under 65536 light samples): the
// spread order measures every part of the film within the first few submissions, and
// sizing by the costliest keeps a budget learnt on cheap pixels from being spent on
// costly ones. Every pixel still receives sample indices 0..spp-1 exactly once and in
// order, so the sums (and the image) are bit-identical to whole passes.
//
// Once the first pass has measured every strip, and a row of the film takes at most half
// the target, the rest is rendered in sweeps of row bands from top to bottom: each sweep
// gives every pixel `count` more samples, as many as one row can take within the target
// (often all that are left), and each band is as many rows as fit. One dispatch then adds
// many samples to each of its pixels one after another (integrators/kernel_common.glsl,
// main), which is faster per sample the more it adds: each invocation's fixed cost is
// spread over more samples, and a pixel's next sample may find what its last one read
// still in the CPU's caches. On lavapipe (2 cores), 16 samples per dispatch rendered
// 1.29-1.34x the samples per CPU second of one sample per dispatch on the 1M-triangle
// bench scene and 1.24x on the Cornell box, 4 samples 1.17-1.25x and 1.17x (penumbra_bench
// --samples-per-dispatch; docs/PERFORMANCE.md, "Round 16"). Whole passes over the film
// are the sweeps whose one band holds every row.
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
    // Pixel samples of the bands handed out so far over the film's pixels: samplesDone()
    // plus the part of a sweep or pass already handed out (for progress and time left).
    double meanSamplesDone() const { return double(m_pixelSamplesDone) / (double(m_width) * m_height); }

private:
    struct Strip {
        uint32_t firstRow = 0, rows = 0;
        uint32_t row = 0, column = 0;  // the next pixel of the current pass, relative row
        double cost = -1.0;            // its last band's seconds per pixel sample; < 0 unknown
        bool done() const { return row >= rows; }
    };
    // Whether every strip's cost is known (once the first pass is done).
    bool allMeasured() const;
    // The costliest strip's cost, or < 0 if none is known.
    double maxCost() const;
    // The next band of the current sweep (see above), starting one if none is under way.
    PassBand nextSweepBand(double target);

    uint32_t m_width, m_height, m_spp;
    uint64_t m_maxPixelSamples;
    uint64_t m_firstBandPixels;
    uint32_t m_sample = 0;
    std::vector<Strip> m_strips;
    std::vector<uint32_t> m_order;    // strip visiting order
    size_t m_nextStrip = 0;           // position in m_order
    double m_fixedSeconds = -1.0;     // the shortest band so far: a bound on each band's fixed cost
    PassBand m_last;                  // the last band handed out (none: no pixel samples)
    bool m_lastInSweep = false;       // it was a sweep's, not one strip's
    int m_lastStrip = -1;             // the strip of the last band, when not a sweep's
    uint32_t m_sweepCount = 0;        // samples per pixel of the current sweep; 0: none under way
    uint32_t m_sweepRow = 0;          // the current sweep's next row
    uint64_t m_pixelSamplesDone = 0;  // of every band handed out
};

}  // namespace penumbra
