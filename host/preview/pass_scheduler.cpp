// Band-of-rows scheduling of progressive passes (see pass_scheduler.h).
#include "preview/pass_scheduler.h"

#include <algorithm>
#include <stdexcept>

namespace penumbra::preview {

PassScheduler::PassScheduler(uint32_t height, uint32_t spp) : m_height(height), m_spp(spp) {
    if (height == 0) throw std::invalid_argument("pass scheduler: the film has no rows");
}

void PassScheduler::restart() {
    m_sample = 0;
    m_row = 0;
}

std::vector<PassSlice> PassScheduler::next(uint64_t rowBudget) {
    std::vector<PassSlice> slices;
    rowBudget = std::max<uint64_t>(rowBudget, 1);
    while (rowBudget > 0 && !finished()) {
        if (m_row == 0 && rowBudget >= m_height) {
            uint32_t count = uint32_t(std::min<uint64_t>(rowBudget / m_height, m_spp - m_sample));
            slices.push_back({m_sample, count, 0, m_height});
            m_sample += count;
            rowBudget -= uint64_t(count) * m_height;
        } else {
            uint32_t band = uint32_t(std::min<uint64_t>(rowBudget, m_height - m_row));
            slices.push_back({m_sample, 1, m_row, band});
            m_row += band;
            rowBudget -= band;
            if (m_row == m_height) {
                m_row = 0;
                ++m_sample;
            }
        }
    }
    return slices;
}

uint64_t adaptRowBudget(uint64_t budget, double seconds, double targetSeconds, uint32_t height) {
    double factor = seconds > 0.0 ? targetSeconds / seconds : 2.0;
    factor = std::clamp(factor, 0.5, 2.0);
    double scaled = double(std::max<uint64_t>(budget, 1)) * factor;
    const uint64_t minimum = std::min<uint64_t>(8, height);
    const uint64_t maximum = uint64_t(256) * height;
    uint64_t rows = uint64_t(std::clamp(scaled, double(minimum), double(maximum)));
    if (rows < height) rows = std::max<uint64_t>(minimum, rows / 8 * 8);
    return rows;
}

}  // namespace penumbra::preview
