// `penumbra render`: load, render on the GPU with progress on stderr, write the output (EXR,
// or a PNG alone when -o ends in .png) and the --png one.
#include <unistd.h>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "cli/commands.h"
#include "cli/denoise_step.h"
#include "cli/slow_step_notice.h"
#include "core/errors.h"
#include "core/phases.h"
#include "core/stop_request.h"
#include "image/image.h"
#include "image/output_check.h"
#include "image/output_format.h"
#include "session/render_session.h"

namespace penumbra {
namespace {

// --denoise: the noisy EXR goes to a temporary file beside the output, which the denoiser
// reads and writes `output` from (whole or not at all); the temporary file never stays.
void writeDenoisedExr(const std::filesystem::path& output, const Image& image) {
    // Hidden, and one per process. Appended piece by piece: "." + name trips GCC 12's -Wrestrict.
    std::string name = ".";
    name.append(output.filename().string()).append(".noisy-").append(std::to_string(getpid())).append(".exr");
    std::filesystem::path noisy = output;
    noisy.replace_filename(name);
    try {
        writeExr(noisy, image);
        denoiseExr(noisy, output);
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(noisy, ignored);
        throw;
    }
    std::filesystem::remove(noisy);
}

}  // namespace

void printNotes(const std::vector<std::string>& notes, bool quiet) {
    if (quiet) return;
    for (const std::string& note : notes) std::cerr << "penumbra: " << note << "\n";
}

int renderCommand(const RenderOptions& options) {
    const auto commandStart = std::chrono::steady_clock::now();
    // Bad usage before bad input: a misnamed output is known without reading the scene.
    std::optional<OutputFormat> format = OutputFormat::Exr;
    if (!options.output.empty()) {
        format = outputFormatOf(options.output);
        if (!format) throw InputError("-o " + outputFormatProblem(options.output));
    }
    // Loading checks the stop flag between chunks (core/stop_request.h); opening the device
    // and compiling kernels do not, and a signal there exits at once.
    clearStopRequest();
    Scene scene = [&] {
        StopPoints loading;
        Phase phase("load");
        Scene loaded = loadScene(options.scene, options.overrides);
        throwIfStopRequested();
        return loaded;
    }();
    std::filesystem::path output = options.output.empty() ? std::filesystem::path(scene.name + ".exr")
                                                           : std::filesystem::path(options.output);
    // Every output is checked before the render, against the scene and each other.
    std::vector<RunFile> outputs{{output, "-o"}};
    if (!options.png.empty()) outputs.push_back({options.png, "--png"});
    checkOutputs(outputs, {{options.scene, "the scene"}});
    if (options.denoise) {
        if (*format != OutputFormat::Exr) throw InputError("--denoise adds a layer to an EXR: -o must end in .exr");
        checkDenoiser();  // before rendering: a missing denoiser costs no render
    }
    printNotes(scene.notes, options.quiet);

    RenderSession session;
    {
        Phase phase("context");
        session.open(options.device);
    }
    const bool showProgress = !options.quiet && isatty(STDERR_FILENO);
    {
        // penumbra:render_seconds is the time spent rendering samples: scene upload, BVH and
        // the driver's shader compilation come before it, here (docs/design/contract-decisions.md, "render_seconds").
        SlowStepNotice compiling("compiling kernels...", showProgress);
        Phase phase("prepare");  // upload, kernel creation and its first dispatch (the JIT)
        session.prepare(scene, false);
    }
    const uint64_t pixels = uint64_t(scene.film.width) * scene.film.height;
    auto progress = [&](const RenderProgress& p) {
        if (!showProgress) return;
        std::fprintf(stderr, "\rpenumbra: %u/%u spp (%.0f%%)  %.2f M samples/s  %.1f s left   ", p.samplesDone,
                     p.samplesTotal, 100.0 * p.shareDone(), p.samplesPerSecond(double(pixels)) * 1e-6, p.secondsLeft());
        std::fflush(stderr);
    };
    // A stop is seen at the next submission (each about 0.25 s, render/pass_bands.h); the
    // stop points last until the outputs are written, so that a signal during the writing
    // lets it finish rather than leave a temporary file behind.
    StopPoints rendering;
    std::optional<Phase> renderPhase(std::in_place, "render");
    Image image = session.render(progress, stopFlag());
    renderPhase.reset();
    const double seconds = image.meta.renderSeconds.value_or(0.0);

    if (stopRequested()) throw std::runtime_error("render interrupted");
    {
        Phase writePhase("write");
        if (*format == OutputFormat::Png) writePng(output, image, options.look);
        else if (options.denoise) writeDenoisedExr(output, image);
        else writeExr(output, image);
        // Each file is whole or absent (atomic_file.h); when the second fails (a full
        // disk), the message says that the first was written.
        if (!options.png.empty()) try {
                writePng(options.png, image, options.look);
            } catch (const std::exception& e) {
                throw std::runtime_error(std::string(e.what()) + " (" + output.string() + " was written)");
            }
    }
    if (showProgress) {
        std::fprintf(stderr, "\r%78s\r", "");  // the progress line
        // Both times named: the rate is over the rendering alone, "in all" is the whole command.
        const double all = std::chrono::duration<double>(std::chrono::steady_clock::now() - commandStart).count();
        std::fprintf(stderr, "penumbra: %u spp in %.2f s of rendering (%.2f M samples/s); %.2f s in all\n",
                     scene.sampler.spp, seconds,
                     seconds > 0 ? double(pixels) * scene.sampler.spp / seconds * 1e-6 : 0.0, all);
    }
    return 0;
}

}  // namespace penumbra
