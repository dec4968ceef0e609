// A one-line notice on a terminal for a step that may take a while with nothing else to show
// (kernel compilation before the first sample): printed only when the step is still running
// after `delay`, erased when it ends, so that fast starts print nothing.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace penumbra {

class SlowStepNotice {
public:
    // Shows "penumbra: TEXT" on stderr after `delay` unless destroyed first; does nothing
    // when `enabled` is false (not a terminal, --quiet).
    SlowStepNotice(std::string text, bool enabled, std::chrono::milliseconds delay = std::chrono::milliseconds(500));
    ~SlowStepNotice();  // erases the line if it was shown
    SlowStepNotice(const SlowStepNotice&) = delete;
    SlowStepNotice& operator=(const SlowStepNotice&) = delete;

    bool shown() const;

private:
    std::string m_text;
    mutable std::mutex m_mutex;
    std::condition_variable m_done;
    bool m_finished = false;
    bool m_shown = false;
    std::thread m_thread;
};

}  // namespace penumbra
