// Progressive accumulation in bounded slices for the preview: which sample index goes to
// which band of rows, frame after frame. Every pixel receives sample indices 0..spp-1
// exactly once and in order (so its sum is the one `penumbra render` computes), and a new
// sample index starts only once every row has the previous one. Timing lives in the loop.
#pragma once

#include <cstdint>
#include <vector>

namespace penumbra::preview {

// `count` passes with sample indices [firstSample, firstSample + count) over rows
// [firstRow, firstRow + rowCount): the arguments of Renderer::recordPasses.
struct PassSlice {
    uint32_t firstSample = 0;
    uint32_t count = 0;
    uint32_t firstRow = 0;
    uint32_t rowCount = 0;
};

class PassScheduler {
public:
    PassScheduler(uint32_t height, uint32_t spp);

    // Back to sample 0, row 0 (after the accumulation was cleared).
    void restart();
    // The next slices, about `rowBudget` rows of one-sample work in all (whole passes
    // when the budget covers the film and the current sample index has not started),
    // at least one row unless finished(). Advances the schedule.
    std::vector<PassSlice> next(uint64_t rowBudget);

    bool finished() const { return m_sample >= m_spp; }
    // Sample indices that every row has; rows [0, rowsAhead()) also have one more.
    uint32_t samplesDone() const { return m_sample; }
    uint32_t rowsAhead() const { return m_row; }
    uint32_t spp() const { return m_spp; }
    uint32_t height() const { return m_height; }

private:
    uint32_t m_height;
    uint32_t m_spp;
    uint32_t m_sample = 0;  // the sample index now being added
    uint32_t m_row = 0;     // the first row that does not have it yet
};

// The next frame's row budget: scaled by target / seconds (at most x2 or /2 per frame, so
// one slow frame does not swing it), a multiple of 8 rows (the kernels' tile height)
// below one film, between 8 rows (or the film height if smaller) and 256 whole passes.
uint64_t adaptRowBudget(uint64_t budget, double seconds, double targetSeconds, uint32_t height);

}  // namespace penumbra::preview
