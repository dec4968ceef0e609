// Where one process's time and memory go, phase by phase (tools/bench/bench/startup reads it):
// with PENUMBRA_PHASES set in the environment, each phase prints one line on stderr when
// it ends,
//     penumbra: phase NAME SECONDS s, rss MIB MiB, peak MIB MiB
// (wall seconds of the phase, resident and peak resident memory of the process at its end).
// Unset, a phase costs one flag test. Phases may nest; each prints its own time.
#pragma once

namespace penumbra {

class Phase {
public:
    explicit Phase(const char* name);
    ~Phase();
    Phase(const Phase&) = delete;
    Phase& operator=(const Phase&) = delete;

    // Whether PENUMBRA_PHASES is set (read once).
    static bool enabled();

private:
    const char* m_name;
    double m_start = 0.0;
};

}  // namespace penumbra
