// `penumbra render`: load, render on the GPU with progress on stderr, write EXR (+ PNG).
#include <unistd.h>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli/commands.h"
#include "image/image.h"
#include "image/output_check.h"
#include "session/render_session.h"

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
    Scene scene = loadScene(options.scene, options.overrides);
    std::filesystem::path output = options.output.empty() ? std::filesystem::path(scene.name + ".exr")
                                                           : std::filesystem::path(options.output);
    // Every output is checked before the render, against the scene and each other.
    std::vector<RunFile> outputs{{output, "-o"}};
    if (!options.png.empty()) outputs.push_back({options.png, "--png"});
    checkOutputs(outputs, {{options.scene, "the scene"}});
    printNotes(scene.notes, options.quiet);

    RenderSession session;
    session.open(options.device);
    // penumbra:render_seconds is the time spent rendering samples: scene upload, BVH and
    // the driver's shader compilation come before it, here (README, "render_seconds").
    session.prepare(scene, false);

    const bool showProgress = !options.quiet && isatty(STDERR_FILENO);
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
    Image image = session.render(progress, &g_interrupted);
    if (showProgress)
        std::fprintf(stderr, "\rpenumbra: %u spp in %.2f s%40s\n", scene.sampler.spp,
                     image.meta.renderSeconds.value_or(0.0), "");

    if (g_interrupted) throw std::runtime_error("render interrupted");
    writeExr(output, image);
    if (!options.png.empty()) writePng(options.png, image);
    return 0;
}

}  // namespace penumbra
