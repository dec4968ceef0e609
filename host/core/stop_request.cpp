// The stop flag and the SIGINT/SIGTERM handler (stop_request.h). The handler touches only
// lock-free atomics and _exit, which are async-signal-safe (POSIX.1-2017, 2.4.3).
#include "core/stop_request.h"

#include <unistd.h>

#include <csignal>

namespace penumbra {
namespace {

std::atomic<bool> g_stop{false};
std::atomic<int> g_stopPoints{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

extern "C" void onStopSignal(int) {
    g_stop = true;
    if (g_stopPoints.load() == 0) _exit(1);
}

}  // namespace

void installStopHandlers() {
    struct sigaction action {};
    action.sa_handler = onStopSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // a read interrupted by the signal goes on; the flag is checked after
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

StopPoints::StopPoints() { ++g_stopPoints; }
StopPoints::~StopPoints() { --g_stopPoints; }

bool stopRequested() { return g_stop.load(); }
void clearStopRequest() { g_stop = false; }
void requestStop() { g_stop = true; }
const std::atomic<bool>* stopFlag() { return &g_stop; }

}  // namespace penumbra
