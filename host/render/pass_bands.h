// Splitting a render into GPU submissions of bounded time, so that a stop (Ctrl-C, Slurm)
// is honoured within a fraction of a second whatever the settings. The film is cut into
// up to 8 horizontal strips, visited in a spread-out order (0, 4, 2, 6, 1, 5, 3, 7). During
// the first pass a submission holds bands of the strips in that order (rows, or a run of
// 8-pixel tiles of one row), as many pixel samples in all as the costliest strip's cost per
// pixel sample lets fit in the time, and at most twice the previous submission's (three times
// where that takes the pass's rest, predicted within the time at its gross cost); once every
// strip is measured, it holds a band of a sweep of row bands (below). Each band is timed on
// its own (gpu/gpu_timer.h), so a submission measures every strip it touched. A band's time
// has a fixed part (on lavapipe under load, tens of milliseconds per dispatch) that is taken
// out before costs are computed, bounded by the shortest band seen. Costs differ across the
// image (sky is far cheaper than a glossy floor under 65536 light samples): the spread order
// measures every part of the film within the first few submissions, and sizing by the
// costliest keeps a budget learnt on cheap pixels from being spent on costly ones. Every
// pixel still receives sample indices 0..spp-1 exactly once and in order, so the sums (and
// the image) are bit-identical to whole passes.
//
// Once the first pass has measured every strip, and a row of the film takes at most half
// the target, the rest is rendered in sweeps of row bands from top to bottom: each sweep
// gives every pixel `count` more samples, as many as one row can take within the target
// (often all that are left), and each band is as many rows as fit, at most twice the pixel
// samples of the last submission or of a pass (four times where even that is predicted to
// take a quarter of the time). One dispatch then adds
// many samples to each of its pixels one after another (integrators/kernel_common.glsl,
// main), which is faster per sample the more it adds: each invocation's fixed cost is
// spread over more samples, and a pixel's next sample may find what its last one read
// still in the CPU's caches. On lavapipe (2 cores), 16 samples per dispatch rendered
// 1.29-1.34x the samples per CPU second of one sample per dispatch on the 1M-triangle
// bench scene and 1.24x on the Cornell box, 4 samples 1.17-1.25x and 1.17x (penumbra_bench
// --samples-per-dispatch; docs/performance-history/round-16.md). Whole passes over the film
// are the sweeps whose one band holds every row.
//
// Why several bands per submission: on lavapipe a submission has a fixed cost of about
// 0.2-0.3 ms (the hand-offs between the host, the queue's thread and the worker threads),
// against about 0.04 ms for a dispatch within one submission (`penumbra_bench --low-spp`).
// One submission per strip made the first pass at least eight submissions: at 256 x 160 on
// 2 cores, renders of 1-8 spp took 1.2-1.9x as long as the same passes in one submission
// (docs/performance-history/round-21.md). The x3 and x4 growth cut a Cornell box of 4 spp from
// five submissions to three: 1.19x (docs/performance-history/round-23.md).
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
    // The most bands one submission holds (the timestamps a GpuTimer needs for it).
    static constexpr uint32_t kMaxBandsPerSubmission = 16;

    // `maxPixelSamples` > 0 caps every submission's pixel samples (tests use it to force small
    // bands).
    // `firstBandPixels`: the pixel samples of the first submission, before anything is measured
    // (Renderer derives it from the rays a pixel sample traces; a tile by default).
    // `maxBands`: the most bands a submission holds, at most kMaxBandsPerSubmission (1 where
    // bands cannot be timed apart, i.e. without timestamps).
    PassBands(uint32_t width, uint32_t height, uint32_t spp, uint64_t maxPixelSamples = 0,
              uint64_t firstBandPixels = kTile, uint32_t maxBands = kMaxBandsPerSubmission);

    // The bands of the next submission, in order, meant to take about `targetSeconds` in
    // all; never empty. `maxPixelSamples` caps their sum. Advances the schedule.
    std::vector<PassBand> next(double targetSeconds);
    // The time each band from the last next() took, in the same order.
    void measured(const std::vector<double>& seconds);

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
        // The same with the band's fixed part left in: an overestimate, never under, even
        // where bands of equal size make the fixed part's bound take all of their time.
        double grossCost = -1.0;
        bool done() const { return row >= rows; }
    };
    // Whether every strip's cost is known (once the first pass is done).
    bool allMeasured() const;
    // The most of the strips' `cost` or `grossCost`, or < 0 if none is known.
    double maxOver(double Strip::*cost) const;
    double maxCost() const { return maxOver(&Strip::cost); }
    double maxGrossCost() const { return maxOver(&Strip::grossCost); }
    // The pixels of the current pass not handed out yet.
    uint64_t passPixelsLeft() const;
    // The next band of the current sweep (see above), starting one if none is under way;
    // `lastPixels`: the pixel samples of the last submission.
    PassBand nextSweepBand(double target, uint64_t lastPixels);
    // The next band of the current pass, of at most `budget` pixel samples (and at least a
    // tile), from the next strip in the spread order with work left.
    PassBand nextStripBand(uint64_t budget);
    // Whether nextStripBand's strip is at the start of a row.
    bool nextStripStartsARow() const;
    // A band handed out, and which strip it is of (-1: a sweep's).
    struct Handed {
        PassBand band;
        int strip = -1;
    };

    uint32_t m_width, m_height, m_spp;
    uint64_t m_maxPixelSamples;
    uint64_t m_firstBandPixels;
    uint32_t m_sample = 0;
    std::vector<Strip> m_strips;
    std::vector<uint32_t> m_order;    // strip visiting order
    size_t m_nextStrip = 0;           // position in m_order
    double m_fixedSeconds = -1.0;     // the shortest band so far: a bound on each band's fixed cost
    uint32_t m_maxBands;              // per submission
    std::vector<Handed> m_handed;     // the bands of the last submission handed out
    uint32_t m_sweepCount = 0;        // samples per pixel of the current sweep; 0: none under way
    uint32_t m_sweepRow = 0;          // the current sweep's next row
    uint64_t m_pixelSamplesDone = 0;  // of every band handed out
};

}  // namespace penumbra
