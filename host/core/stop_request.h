// SIGINT and SIGTERM (Ctrl-C, kill, Slurm's scancel and time limit): the process exits with
// status 1 (README, "Exit status"), writing nothing half-done. main installs the handlers
// first thing, so that no signal finds the default action (which would exit 128 + N).
// Where a command can stop at points of its own, it holds a StopPoints scope: a signal
// then only sets the flag, which the loaders (input files, image decoding, environment
// maps), the render loop and the batch loop check; writing an output finishes first.
// Outside any such scope the handler ends the process at once with _exit(1): nothing of
// that time (opening the device, compiling kernels) is left half-written.
#pragma once

#include <atomic>
#include <stdexcept>

namespace penumbra {

// Installs the handlers for SIGINT and SIGTERM; idempotent.
void installStopHandlers();

// While one of these lives, a signal sets the flag instead of ending the process.
class StopPoints {
public:
    StopPoints();
    ~StopPoints();
    StopPoints(const StopPoints&) = delete;
    StopPoints& operator=(const StopPoints&) = delete;
};

// Whether a stop was asked for (reset by clearStopRequest, e.g. at the start of a command).
bool stopRequested();
void clearStopRequest();
// As a signal would: sets the flag (tests, and code that stops for a reason of its own).
void requestStop();
// The flag itself, for code that takes a cancel pointer (Renderer::renderAll).
const std::atomic<bool>* stopFlag();

// Thrown at a stop point after a stop was asked for; a runtime failure (exit status 1).
class Stopped : public std::runtime_error {
public:
    Stopped() : std::runtime_error("interrupted") {}
};
// Throws Stopped when a stop was asked for: called between chunks of long loads.
inline void throwIfStopRequested() {
    if (stopRequested()) throw Stopped();
}

}  // namespace penumbra
