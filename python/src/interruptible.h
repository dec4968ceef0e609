// Running renderer work from Python: on a thread of its own with the GIL released, while
// the calling thread watches for signals. Python runs signal handlers only in the main
// thread, and only when that thread checks for them (PyErr_CheckSignals); a caller blocked
// in C++ would never check, so Ctrl-C would wait for the render to end.
#pragma once

#include <atomic>
#include <chrono>
#include <future>
#include <utility>

#include <pybind11/pybind11.h>

namespace penumbra::python {

// How often the waiting thread runs Python's signal handlers. Ctrl-C is noticed within this
// and then stops the render at its next submission (about 0.25 s, render/pass_bands.h).
constexpr std::chrono::milliseconds kSignalCheckPeriod{50};

// Calls work(cancel) on another thread and returns its result. Meanwhile, every
// kSignalCheckPeriod, the caller takes the GIL and runs the signal handlers; when one raises
// (Ctrl-C: KeyboardInterrupt), `cancel` becomes true, the work is awaited (it stops at
// its next check of `cancel`) and the handler's exception propagates
// (pybind11::error_already_set). `work` must not touch Python objects.
template <class Work>
auto runInterruptible(Work&& work) {
    std::atomic<bool> cancel{false};
    auto result = std::async(std::launch::async, [&] { return work(cancel); });
    while (true) {
        {
            pybind11::gil_scoped_release release;
            if (result.wait_for(kSignalCheckPeriod) == std::future_status::ready) break;
        }
        if (PyErr_CheckSignals() != 0) {
            cancel = true;
            {
                pybind11::gil_scoped_release release;
                result.wait();  // its "render interrupted" is the signal's doing: dropped
            }
            throw pybind11::error_already_set();
        }
    }
    return result.get();
}

}  // namespace penumbra::python
