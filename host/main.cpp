// The command line (SCENE_FORMAT.md): parses arguments, runs one subcommand, and maps
// failures to exit statuses: 0 success, 2 bad usage or bad input, 1 anything else.
#include <cstdio>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/exit_status.h"
#include "core/input_file.h"
#include "core/stop_request.h"

using namespace penumbra;

namespace {

void printError(const std::string& message) { printErrorLine("penumbra", message); }

void addRenderOptions(CLI::App* cmd, RenderOptions& options, std::vector<std::string>& sets, std::string& spp,
                      std::string& seed, std::string& width, std::string& height, std::string& aov) {
    cmd->add_option("scene", options.scene, "scene file (.json) or glTF model (.gltf/.glb)")->required();
    cmd->add_option("--set", sets, "override a scene value by its JSON path: PATH=VALUE (repeatable)")
        ->allow_extra_args(false);
    cmd->add_option("--spp", spp, "samples per pixel (= --set sampler.spp=N)");
    cmd->add_option("--seed", seed, "random seed (= --set sampler.seed=S)");
    cmd->add_option("--width", width, "film width (= --set film.width=W)");
    cmd->add_option("--height", height, "film height (= --set film.height=H)");
    cmd->add_option("--aov", aov, "AOV layers beside R, G, B: a,b,... (= --set film.aovs=[\"a\",\"b\",...])");
    cmd->add_option("--device", options.device, "Vulkan device index (see 'penumbra devices'; or PENUMBRA_DEVICE)");
    cmd->add_flag("--quiet", options.quiet, "no progress or notes on stderr");
    cmd->add_option("--exposure", options.look.exposure, "PNG and preview: radiance times 2^EV (default 0)")
        ->check(CLI::Range(-64.0f, 64.0f));
    cmd->add_option_function<std::string>(
           "--tonemap", [&options](const std::string& name) { options.look.curve = *toneCurveFromName(name); },
           "PNG and preview: clamp (default) or filmic (ACES fit)")
        ->check(CLI::IsMember({"clamp", "filmic"}));
}

// "albedo,depth" -> ["albedo","depth"], checked later as film.aovs is.
std::string aovListJson(const std::string& list) {
    nlohmann::json names = nlohmann::json::array();
    size_t start = 0;
    for (size_t comma; (comma = list.find(',', start)) != std::string::npos; start = comma + 1)
        names.push_back(list.substr(start, comma - start));
    names.push_back(list.substr(start));
    return names.dump();
}

std::vector<Override> collectOverrides(const std::vector<std::string>& sets, const std::string& spp,
                                       const std::string& seed, const std::string& width, const std::string& height,
                                       const std::string& aov) {
    std::vector<Override> overrides;
    for (const std::string& s : sets) overrides.push_back(parseOverride(s));
    if (!spp.empty()) overrides.push_back({"sampler.spp", spp});
    if (!seed.empty()) overrides.push_back({"sampler.seed", seed});
    if (!width.empty()) overrides.push_back({"film.width", width});
    if (!height.empty()) overrides.push_back({"film.height", height});
    if (!aov.empty()) overrides.push_back({"film.aovs", aovListJson(aov)});
    return overrides;
}

}  // namespace

int main(int argc, char** argv) {
    // First thing: from here on SIGINT and SIGTERM exit with status 1, never the default
    // action's 130/143 (core/stop_request.h).
    installStopHandlers();
    CLI::App app{"penumbra: direct illumination on Vulkan compute"};
    app.require_subcommand(0, 1);
    bool version = false;
    app.add_flag("--version", version, "print the version and the Vulkan driver, one line");

    RenderOptions render;
    std::vector<std::string> sets;
    std::string spp, seed, width, height, aov;
    CLI::App* renderCmd = app.add_subcommand("render", "render a scene or glTF model to OpenEXR");
    addRenderOptions(renderCmd, render, sets, spp, seed, width, height, aov);
    renderCmd->add_option("-o,--output", render.output,
                          "output .exr, or .png for an sRGB PNG alone (default: SCENE-stem.exr here)");
    renderCmd->add_option("--png", render.png, "also write an sRGB 8-bit PNG");
    renderCmd->add_flag("--denoise", render.denoise,
                        "add a denoised layer to the EXR (Open Image Denoise; needs pip install penumbra[denoise])");

    BatchOptions batch;
    CLI::App* batchCmd = app.add_subcommand("batch", "render every job of a job file (docs/BATCH.md)");
    batchCmd->add_option("jobs", batch.jobFile, "job file (.json)")->required();
    // Ranges as integers: CLI11's PositiveNumber printed its range as 310-digit doubles.
    batchCmd->add_option("--task", batch.task, "run only jobs j with j % TASKS == TASK (0-based)")
        ->check(CLI::Range(0, std::numeric_limits<int>::max()));
    batchCmd->add_option("--tasks", batch.tasks, "number of tasks the jobs are split into")
        ->check(CLI::Range(1, std::numeric_limits<int>::max()));
    batchCmd->add_option("--device", batch.device, "Vulkan device index (see 'penumbra devices'; or PENUMBRA_DEVICE)");
    batchCmd->add_flag("--list", batch.list, "print the jobs (of this task) and exit, rendering nothing");
    batchCmd->add_flag("--quiet", batch.quiet, "no per-job progress or notes on stderr (failures and summary stay)");

    PreviewOptions preview;
    CLI::App* previewCmd = app.add_subcommand("preview", "show a scene converging in a window; change camera and strategy live");
    addRenderOptions(previewCmd, preview.base, sets, spp, seed, width, height, aov);
    previewCmd->add_option("--frames", preview.frames, "exit after N frames, converged ones included (default: when the window closes)");
    previewCmd->add_option("--screenshot", preview.screenshot, "at exit, write the tone-mapped image as PNG");
    previewCmd->add_option("--script", preview.script, "timed input events (format below)");
    previewCmd->add_option("--rows-per-frame", preview.rowsPerFrame, "rows of work per frame (default: adaptive)");
    previewCmd->footer(previewHelp());

    std::vector<std::string> mergeInputs;
    std::string mergeOutput;
    CLI::App* mergeCmd = app.add_subcommand("merge", "average partial renders weighted by their spp");
    mergeCmd->add_option("inputs", mergeInputs, "partial renders (EXR)")->required();
    mergeCmd->add_option("-o,--output", mergeOutput, "merged EXR")->required();

    std::string compareA, compareB;
    CLI::App* compareCmd = app.add_subcommand("compare", "error metrics between two images (b is the reference)");
    compareCmd->add_option("a", compareA, "image")->required();
    compareCmd->add_option("b", compareB, "reference image")->required();

    CLI::App* devicesCmd = app.add_subcommand("devices", "list Vulkan devices; '*' marks the one used");

    // Files that scenes, glTF models and job files name are used only from inside their own
    // folder unless the inputs are trusted (docs/design/contract-decisions.md, "glTF file access"; docs/BATCH.md).
    bool anyPath = false;
    for (CLI::App* cmd : {renderCmd, batchCmd, previewCmd})
        cmd->add_flag("--allow-any-path", anyPath,
                      "trusted inputs: let scenes, glTF models and job files name files outside their folder");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help
        printError(e.what() + std::string(" (see penumbra --help)"));
        return 2;
    }

    if (version) return runReportingErrors("penumbra", versionCommand);
    if (app.get_subcommands().empty()) {
        printError("a command is required: render, preview, batch, merge, compare or devices (see penumbra --help)");
        return 2;
    }
    setAllowAnyPath(anyPath);
    return runReportingErrors("penumbra", [&]() -> int {
        if (renderCmd->parsed()) {
            render.overrides = collectOverrides(sets, spp, seed, width, height, aov);
            return renderCommand(render);
        }
        if (batchCmd->parsed()) return batchCommand(batch);
        if (previewCmd->parsed()) {
            preview.base.overrides = collectOverrides(sets, spp, seed, width, height, aov);
            return previewCommand(preview);
        }
        if (mergeCmd->parsed()) return mergeCommand(mergeInputs, mergeOutput);
        if (compareCmd->parsed()) return compareCommand(compareA, compareB);
        if (devicesCmd->parsed()) return devicesCommand();
        return 2;
    });
}
