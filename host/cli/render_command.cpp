// `penumbra render`: load, render on the GPU with progress on stderr, write the output (EXR,
// or a PNG alone when -o ends in .png) and the --png one.
#include <unistd.h>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli/commands.h"
#include "core/errors.h"
#include "gpu/context.h"
#include "image/image.h"
#include "image/output_check.h"
#include "image/output_format.h"
#include "render/renderer.h"

namespace penumbra {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void onInterrupt(int) { g_interrupted = true; }

}  // namespace

void printNotes(const std::vector<std::string>& notes, bool quiet) {
    if (quiet) return;
    for (const std::string& note : notes) std::cerr << "penumbra: " << note << "\n";
}

int renderCommand(const RenderOptions& options) {
    // Bad usage before bad input: a misnamed output is known without reading the scene.
    std::optional<OutputFormat> format = OutputFormat::Exr;
    if (!options.output.empty()) {
        format = outputFormatOf(options.output);
        if (!format) throw InputError("-o " + outputFormatProblem(options.output));
    }
    Scene scene = loadScene(options.scene, options.overrides);
    std::filesystem::path output = options.output.empty() ? std::filesystem::path(scene.name + ".exr")
                                                           : std::filesystem::path(options.output);
    // Every output is checked before the render, against the scene and each other.
    std::vector<RunFile> outputs{{output, "-o"}};
    if (!options.png.empty()) outputs.push_back({options.png, "--png"});
    checkOutputs(outputs, {{options.scene, "the scene"}});
    printNotes(scene.notes, options.quiet);

    gpu::ContextOptions contextOptions;
    contextOptions.deviceIndex = options.device;
    gpu::Context context(contextOptions);

    const bool showProgress = !options.quiet && isatty(STDERR_FILENO);
    Renderer renderer(context, scene);
    // penumbra:render_seconds is the time spent rendering samples: scene upload, BVH and
    // the driver's shader compilation come before it (README, "render_seconds").
    renderer.compileKernel();
    auto start = std::chrono::steady_clock::now();
    const uint64_t pixels = uint64_t(scene.film.width) * scene.film.height;
    auto progress = [&](const RenderProgress& p) {
        if (!showProgress) return;
        std::fprintf(stderr, "\rpenumbra: %u/%u spp (%.0f%%)  %.2f M samples/s  %.1f s left   ", p.samplesDone,
                     p.samplesTotal, 100.0 * p.shareDone(), p.samplesPerSecond(double(pixels)) * 1e-6, p.secondsLeft());
        std::fflush(stderr);
    };
    // A stop is seen at the next submission (each about 0.25 s, render/pass_bands.h); the
    // handlers stay until the outputs are written, so that a signal during the writing
    // lets it finish rather than leave a temporary file behind.
    g_interrupted = false;
    auto previousInt = std::signal(SIGINT, onInterrupt);
    auto previousTerm = std::signal(SIGTERM, onInterrupt);
    struct RestoreHandlers {
        void (*sigint)(int);
        void (*sigterm)(int);
        ~RestoreHandlers() {
            std::signal(SIGINT, sigint);
            std::signal(SIGTERM, sigterm);
        }
    } restore{previousInt, previousTerm};
    renderer.renderAll(progress, &g_interrupted);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (showProgress) std::fprintf(stderr, "\rpenumbra: %u spp in %.2f s%40s\n", scene.sampler.spp, seconds, "");

    Image image = renderer.readback(seconds);
    if (g_interrupted) throw std::runtime_error("render interrupted");
    if (*format == OutputFormat::Png) writePng(output, image, options.look);
    else writeExr(output, image);
    if (!options.png.empty()) writePng(options.png, image, options.look);
    return 0;
}

}  // namespace penumbra
