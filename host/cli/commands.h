// The subcommands of the penumbra program, one function each; main.cpp only parses the
// command line and maps exceptions to exit statuses (InputError 2, anything else 1).
#pragma once

#include <string>
#include <vector>

#include "image/tone_map.h"
#include "scene/load.h"

namespace penumbra {

struct RenderOptions {
    std::string scene;
    std::string output;     // .exr or .png (image/output_format.h); empty: <scene stem>.exr here
    std::string png;        // empty: no PNG
    ToneLook look;          // --exposure and --tonemap, for PNGs and the preview (never the EXR)
    std::vector<Override> overrides;
    int device = -1;
    bool quiet = false;
    bool denoise = false;  // --denoise: add the "denoised" layer (cli/denoise_step.h)
};

// penumbra batch (docs/BATCH.md).
struct BatchOptions {
    std::string jobFile;
    int device = -1;
    bool quiet = false;
    bool list = false;  // print this task's jobs (index, output, origin) to stdout instead
    int task = -1;      // with tasks: run only jobs j with j % tasks == task
    int tasks = -1;
};

int renderCommand(const RenderOptions& options);
int batchCommand(const BatchOptions& options);

// `penumbra preview`: the scene in a window (host/preview/). `base` holds the options it
// shares with render (scene, overrides, device, quiet); output and png are unused.
struct PreviewOptions {
    RenderOptions base;
    unsigned frames = 0;        // exit after N frames (0: when the window closes)
    std::string screenshot;     // PNG of the tone-mapped film at exit
    std::string script;         // input script (host/preview/input_script.h)
    unsigned rowsPerFrame = 0;  // 0: adaptive
};

int previewCommand(const PreviewOptions& options);
// The preview's keys and mouse bindings, and the input script format, for --help.
std::string previewHelp();
int mergeCommand(const std::vector<std::string>& inputs, const std::string& output);
int compareCommand(const std::string& a, const std::string& b);
int devicesCommand();
// `penumbra --version`: one line on stdout, the version and the Vulkan device and driver
// the automatic choice (or PENUMBRA_DEVICE) would use.
int versionCommand();

// Prints one-line notes to stderr unless quiet (e.g. "model.glb: no lights ...").
void printNotes(const std::vector<std::string>& notes, bool quiet);

}  // namespace penumbra
