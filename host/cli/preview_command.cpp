// `penumbra preview`: load the scene (with render's overrides), then hand it to the
// preview loop (host/preview/). Builds without GLFW say so and exit 1.
#include <stdexcept>

#include "cli/commands.h"
#include "image/output_check.h"
#include "preview/input_script.h"
#include "preview/key_bindings.h"
#include "preview/preview_loop.h"

namespace penumbra {

std::string previewHelp() {
    return "Keys and mouse:\n" + preview::keyHelp() +
           "\n\n--script FILE: one event per line, applied before frame N renders (frames count from 1):\n"
           "  frame N key K          K: 1 2 3 4 h s + - p r q esc\n"
           "  frame N drag DX DY [left|right|middle]\n"
           "  frame N scroll STEPS\n"
           "  frame N resize W H\n"
           "On exit, 'preview: DONE/TARGET spp' goes to stderr (not with --quiet).";
}

int previewCommand(const PreviewOptions& options) {
    // Bad input is exit 2 whether or not a window can be had: check it first.
    const RenderOptions& base = options.base;
    Scene scene = loadScene(base.scene, base.overrides);
    preview::PreviewSettings settings;
    if (!options.script.empty()) settings.script = preview::loadInputScript(options.script);
    settings.frames = options.frames;
    settings.screenshot = options.screenshot;
    settings.rowsPerFrame = options.rowsPerFrame;
    settings.deviceIndex = base.device;
    settings.quiet = base.quiet;
    settings.look = base.look;
    if (!settings.screenshot.empty()) {
        std::vector<RunFile> inputs{{base.scene, "the scene"}};
        if (!options.script.empty()) inputs.push_back({options.script, "--script"});
        checkOutputs({{settings.screenshot, "--screenshot"}}, inputs);
    }
#ifdef PENUMBRA_HAVE_GLFW
    printNotes(scene.notes, base.quiet);
    preview::runPreview(scene, settings);
    return 0;
#else
    throw std::runtime_error("this penumbra was built without GLFW (libglfw3-dev), so it has no preview window");
#endif
}

}  // namespace penumbra
