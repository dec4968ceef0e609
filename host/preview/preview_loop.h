// The interactive preview (`penumbra preview`): a window that shows the scene converging,
// frame by frame, with live camera and integrator changes. Each frame handles input, adds
// a bounded slice of passes (pass_scheduler.h) and tone-maps the accumulation to the
// window; once the scene's spp is reached it blocks in the window system's event wait.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "image/tone_map.h"
#include "preview/input_script.h"
#include "scene/scene.h"

namespace penumbra::preview {

struct PreviewSettings {
    uint32_t frames = 0;               // exit after this many frames (0: when the window closes)
    std::filesystem::path screenshot;  // PNG of the tone-mapped film written at exit (empty: none)
    std::vector<ScriptEvent> script;   // timed input (input_script.h)
    uint32_t rowsPerFrame = 0;         // rows of one-sample work per frame; 0: adaptive (~40 ms a frame)
    int deviceIndex = -1;              // as --device; -1: PENUMBRA_DEVICE or the automatic choice
    bool quiet = false;                // no notes and no final "preview: D/T spp" line on stderr
    ToneLook look;                     // --exposure (where the +/- keys start) and --tonemap
};

// Opens the window and runs until it is closed, Q / Esc, or settings.frames frames. Throws
// std::runtime_error (one line) when no window can be opened or the device cannot present.
void runPreview(const Scene& scene, const PreviewSettings& settings);

}  // namespace penumbra::preview
