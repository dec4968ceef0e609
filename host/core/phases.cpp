// Phase timing (see phases.h).
#include "core/phases.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace penumbra {
namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// VmRSS and VmHWM of /proc/self/status, in MiB (0 where they cannot be read).
void residentMemory(double* rss, double* peak) {
    *rss = *peak = 0.0;
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return;
    char line[256];
    while (std::fgets(line, sizeof line, f)) {
        long kib = 0;
        if (std::sscanf(line, "VmRSS: %ld kB", &kib) == 1) *rss = double(kib) / 1024.0;
        if (std::sscanf(line, "VmHWM: %ld kB", &kib) == 1) *peak = double(kib) / 1024.0;
    }
    std::fclose(f);
}

}  // namespace

bool Phase::enabled() {
    static const bool on = std::getenv("PENUMBRA_PHASES") != nullptr;
    return on;
}

Phase::Phase(const char* name) : m_name(name) {
    if (enabled()) m_start = now();
}

Phase::~Phase() {
    if (!enabled()) return;
    const double seconds = now() - m_start;
    double rss, peak;
    residentMemory(&rss, &peak);
    std::fprintf(stderr, "penumbra: phase %s %.3f s, rss %.0f MiB, peak %.0f MiB\n", m_name, seconds, rss, peak);
}

}  // namespace penumbra
