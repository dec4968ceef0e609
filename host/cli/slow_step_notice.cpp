#include "cli/slow_step_notice.h"

#include <cstdio>

namespace penumbra {

SlowStepNotice::SlowStepNotice(std::string text, bool enabled, std::chrono::milliseconds delay)
    : m_text(std::move(text)) {
    if (!enabled) return;
    m_thread = std::thread([this, delay] {
        std::unique_lock lock(m_mutex);
        if (m_done.wait_for(lock, delay, [this] { return m_finished; })) return;
        std::fprintf(stderr, "\rpenumbra: %s", m_text.c_str());
        std::fflush(stderr);
        m_shown = true;
    });
}

SlowStepNotice::~SlowStepNotice() {
    {
        std::lock_guard lock(m_mutex);
        m_finished = true;
    }
    m_done.notify_all();
    if (m_thread.joinable()) m_thread.join();
    if (m_shown) {
        // Blank the notice so that the progress line that follows starts on a clean line.
        std::fprintf(stderr, "\r%*s\r", int(m_text.size()) + 10, "");
        std::fflush(stderr);
    }
}

bool SlowStepNotice::shown() const {
    std::lock_guard lock(m_mutex);
    return m_shown;
}

}  // namespace penumbra
