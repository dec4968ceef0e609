// `penumbra batch`: renders the jobs of a job file (batch/job_file.h) in one process with
// one Vulkan context, skipping jobs whose output is already complete, so that an
// interrupted batch resumes. Reuse across jobs: compute pipelines always (KernelCache),
// the uploaded scene when consecutive jobs' scenes, as loaded, differ only in camera,
// sampler or integrator options (sharesUpload).
// Exit status rule and summary: docs/BATCH.md.
#include <unistd.h>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "batch/job_file.h"
#include "cli/commands.h"
#include "cli/slow_step_notice.h"
#include "core/errors.h"
#include "core/exit_status.h"
#include "core/stop_request.h"
#include "image/image.h"
#include "image/image_file.h"
#include "image/output_check.h"
#include "image/output_format.h"
#include "scene/integrator_json.h"
#include "scene/integrator_options.h"
#include "session/render_session.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string oneLine(std::string text) {
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    return text;
}

// Empty when `output` holds this job's finished render: an EXR that reads back whole
// (writes are atomic, so a partial one cannot exist; a foreign or damaged file fails
// here) and whose header matches the job: size, spp, seed, sample_offset, integrator,
// sampler and AOV layers.
// Otherwise why not, for the progress line.
std::string incompleteReason(const fs::path& output, const Scene& scene) {
    std::error_code ec;
    if (!fs::exists(output, ec)) return "missing";
    if (outputFormatOf(output) == OutputFormat::Png) {
        // A PNG records no render settings: one that decodes at the film's size is taken
        // as this job's (docs/BATCH.md); writes are atomic, so it is whole.
        try {
            const ImageFile png = readImageFile(output, ColorDecode::Linear);
            if (png.width != scene.film.width || png.height != scene.film.height) return "other film size";
            return {};
        } catch (const std::exception&) {
            return "unreadable";
        }
    }
    Image image;
    try {
        image = readExr(output);
    } catch (const std::exception&) {
        return "unreadable";
    }
    const ImageMetadata& m = image.meta;
    if (!m.spp) return "no penumbra:spp";
    if (*m.spp != int64_t(scene.sampler.spp))
        return "has " + std::to_string(*m.spp) + " spp, job wants " + std::to_string(scene.sampler.spp);
    if (image.width != scene.film.width || image.height != scene.film.height) return "other film size";
    if (m.seed && *m.seed != int64_t(scene.sampler.seed)) return "other seed";
    if (m.sampleOffset && *m.sampleOffset != int64_t(scene.sampler.sampleOffset)) return "other sample_offset";
    // A merged file may match spp, seed and offset while holding other samples.
    const int64_t first = scene.sampler.sampleOffset;
    if (m.pieces && *m.pieces != std::vector<SamplePiece>{{scene.sampler.seed, first, first + scene.sampler.spp}})
        return "other sample pieces";
    if (m.integrator && *m.integrator != integratorJson(scene.integrator).dump()) return "other integrator";
    // Absent: rendered before the sampler option, with independent samples.
    if (m.sampler.value_or("independent") != toName(scene.sampler.type)) return "other sampler";
    // A render that lacks a layer the job asks for (film.aovs), or has others, is not its output.
    std::vector<std::string> aovs;
    for (const AovLayer& layer : image.aovs) aovs.push_back(layer.name);
    if (aovs != scene.film.aovs) return "other AOVs";
    return {};
}

// Every output of the job file against every other and against every input (the job
// file and each job's scene), however spelled, before anything runs: exit 2 naming the
// job file and the job's JSON path. All jobs, not only this task's: the tasks of one
// job file run at the same time.
void checkJobFiles(const fs::path& jobFile, const std::vector<BatchJob>& jobs) {
    std::vector<RunFile> outputs, inputs{{jobFile, "the job file"}};
    for (const BatchJob& job : jobs) {
        // origin is the entry's JSON path, then " sweep N (values)" for a sweep.
        const size_t space = job.origin.find(' ');
        const std::string entry = job.origin.substr(0, space);
        const std::string sweep = space == std::string::npos ? "" : job.origin.substr(space);
        outputs.push_back({job.output, entry + ".output" + sweep});
        if (!job.png.empty()) outputs.push_back({job.png, entry + ".png" + sweep});
        inputs.push_back({job.scene, entry + ".scene" + sweep});
    }
    checkDistinctFiles(outputs, inputs, jobFile.string() + ": ");
}

struct Totals {
    size_t rendered = 0, skipped = 0, failedInput = 0, failedRuntime = 0, notRun = 0;
    double renderSeconds = 0.0;
    double samples = 0.0;  // pixel samples rendered
    size_t uploads = 0, uploadsReused = 0;
};

// Task I of N from --task/--tasks (0 of 1 without them); bad input when they don't fit.
struct TaskShare {
    size_t task = 0, tasks = 1;
};

TaskShare taskShare(const BatchOptions& options) {
    if ((options.task >= 0) != (options.tasks >= 0))
        throw InputError("--task and --tasks go together (task I of N, 0 <= I < N)");
    TaskShare share;
    share.tasks = options.tasks >= 0 ? size_t(options.tasks) : 1;
    share.task = options.task >= 0 ? size_t(options.task) : 0;
    if (share.tasks == 0 || share.task >= share.tasks)
        throw InputError("--task " + std::to_string(share.task) + " --tasks " + std::to_string(share.tasks) +
                         ": need 0 <= task < tasks");
    return share;
}

// The progress ticker on a terminal: one line rewritten in place, blanked before the next
// line of output.
class Ticker {
public:
    explicit Ticker(bool enabled) : m_enabled(enabled) {}
    bool enabled() const { return m_enabled; }
    void show(const std::string& tag, const RenderProgress& p, double pixels) {
        if (!m_enabled) return;
        end();
        m_width = std::fprintf(stderr, "penumbra: %s: %u/%u spp (%.0f%%)  %.2f M samples/s", tag.c_str(), p.samplesDone,
                               p.samplesTotal, 100.0 * p.shareDone(), p.samplesPerSecond(pixels) * 1e-6);
        std::fflush(stderr);
    }
    void end() {
        if (m_width > 0) std::fprintf(stderr, "\r%*s\r", m_width, "");
        m_width = 0;
    }

private:
    bool m_enabled;
    int m_width = 0;  // of the ticker line on the terminal
};

// A job whose output is already complete: its PNG is written from the EXR when missing.
void skipCompleteJob(const BatchJob& job, const std::string& tag, bool progressLines) {
    std::error_code ec;
    bool pngMissing = !job.png.empty() && !fs::exists(job.png, ec);
    if (pngMissing) writePng(job.png, readExr(job.output));
    if (progressLines)
        std::fprintf(stderr, "penumbra: %s: skipped, already complete%s\n", tag.c_str(),
                     pngMissing ? " (PNG written from it)" : "");
}

// The device side of a batch, kept across jobs (session/render_session.h; after a failure
// the session holds no scene, and uploads the next anew).
struct Device {
    RenderSession session;

    // Makes the job's scene the next render, keeping the upload when the scene as loaded
    // differs from the uploaded one only where retargeting covers it (scene.h sharesUpload;
    // by content, so that a scene file edited during the batch is uploaded anew). True when
    // the upload was reused.
    bool prepare(const Scene& scene) {
        const Scene* uploaded = session.uploadedScene();
        const bool reuse = session.prepare(scene, uploaded && sharesUpload(*uploaded, scene));
        return reuse;
    }
};

struct JobTimes {
    double seconds;        // from jobStart: with upload and pipeline, as `render` counts
    double renderSeconds;  // rendering alone
};

// Renders `scene` into the job's outputs (the session must hold it) and counts it in `totals`.
JobTimes renderJob(Device& device, const BatchJob& job, const Scene& scene, const std::string& tag, Ticker& ticker,
                   Clock::time_point jobStart, Totals& totals) {
    const double pixels = double(scene.film.width) * scene.film.height;
    auto progress = [&](const RenderProgress& p) { ticker.show(tag, p, pixels); };
    Image image = device.session.render(progress, stopFlag());
    const double renderSeconds = image.meta.renderSeconds.value_or(0.0);
    const double seconds = secondsSince(jobStart);
    if (outputFormatOf(job.output) == OutputFormat::Png) writePng(job.output, image);
    else writeExr(job.output, image);
    if (!job.png.empty()) try {
            writePng(job.png, image);
        } catch (const std::exception& e) {
            // As `render` says it; the next run of the batch writes the PNG from the EXR.
            throw std::runtime_error(std::string(e.what()) + " (" + job.output.string() + " was written)");
        }
    ++totals.rendered;
    totals.renderSeconds += renderSeconds;
    totals.samples += pixels * scene.sampler.spp;
    return {seconds, renderSeconds};
}

void printSummary(const Totals& totals, size_t jobsOfTask, size_t jobsInFile, const TaskShare& share,
                  Clock::time_point start, const Device& device) {
    const size_t failed = totals.failedInput + totals.failedRuntime;
    char scope[64] = "";
    if (share.tasks > 1) std::snprintf(scope, sizeof scope, "task %zu of %zu, ", share.task, share.tasks);
    std::fprintf(stderr,
                 "penumbra: batch %s: rendered %zu, skipped %zu, failed %zu, not run %zu, of %zu jobs (%s%zu in the "
                 "file) in %.2f s in all; %.2f M samples/s while rendering; scene uploads %zu, reused %zu; pipelines "
                 "created %zu, reused %zu\n",
                 stopRequested() ? "interrupted" : "done", totals.rendered, totals.skipped, failed, totals.notRun,
                 jobsOfTask, scope, jobsInFile, secondsSince(start),
                 totals.renderSeconds > 0 ? totals.samples / totals.renderSeconds * 1e-6 : 0.0, totals.uploads,
                 totals.uploadsReused, device.session.pipelinesCreated(), device.session.pipelinesReused());
}

}  // namespace

int batchCommand(const BatchOptions& options) {
    const auto start = Clock::now();
    const TaskShare share = taskShare(options);
    const std::vector<BatchJob> all = loadJobFile(options.jobFile);
    checkJobFiles(options.jobFile, all);
    std::vector<size_t> mine;  // this task's share: jobs j with j % tasks == task
    for (size_t j = share.task; j < all.size(); j += share.tasks) mine.push_back(j);

    if (options.list) {
        for (size_t j : mine)
            std::printf("%zu\t%s\t%s\n", j, all[j].output.string().c_str(), all[j].origin.c_str());
        return 0;
    }

    const bool progressLines = !options.quiet;
    Ticker ticker(progressLines && isatty(STDERR_FILENO));
    Totals totals;
    Device device;

    // SIGINT and SIGTERM (Slurm's scancel and time limit) stop the batch at the next stop
    // point: between jobs, or inside one while it loads or renders (core/stop_request.h).
    clearStopRequest();
    StopPoints stopPoints;

    for (size_t n = 0; n < mine.size(); ++n) {
        const BatchJob& job = all[mine[n]];
        char counter[64];
        std::snprintf(counter, sizeof counter, "[%zu/%zu] job %zu ", n + 1, mine.size(), mine[n]);
        const std::string tag = counter + job.output.string();
        if (stopRequested()) {
            totals.notRun = mine.size() - n;
            break;
        }
        try {
            Scene scene = loadScene(job.scene, job.overrides);
            std::string why = incompleteReason(job.output, scene);
            if (why.empty()) {
                skipCompleteJob(job, tag, progressLines);
                ++totals.skipped;
                continue;
            }
            // Runtime failure (status 1) before any rendering; the directory is created.
            checkWritable(job.output, true);
            if (!job.png.empty()) checkWritable(job.png, true);
            printNotes(scene.notes, options.quiet);

            try {
                device.session.open(options.device);
            } catch (const std::exception& e) {
                // No device for this job means none for the others: stop here.
                std::fprintf(stderr, "penumbra: %s: failed: %s\n", tag.c_str(), oneLine(e.what()).c_str());
                ++totals.failedRuntime;
                totals.notRun = mine.size() - n - 1;
                break;
            }
            const auto jobStart = Clock::now();
            std::optional<SlowStepNotice> compiling(std::in_place, "compiling kernels...", ticker.enabled());
            const bool reuse = device.prepare(scene);  // compiles the kernel: start-up, not rendering
            compiling.reset();
            ++(reuse ? totals.uploadsReused : totals.uploads);
            const JobTimes times = renderJob(device, job, scene, tag, ticker, jobStart, totals);
            ticker.end();
            const double pixelSamples = double(scene.film.width) * scene.film.height * scene.sampler.spp;
            if (progressLines)
                std::fprintf(stderr,
                             "penumbra: %s: rendered %u spp in %.2f s of rendering (%.2f M samples/s); %.2f s in all "
                             "(%s%s)\n",
                             tag.c_str(), scene.sampler.spp, times.renderSeconds,
                             times.renderSeconds > 0 ? pixelSamples / times.renderSeconds * 1e-6 : 0.0, times.seconds,
                             reuse ? "scene upload reused" : "scene uploaded",
                             why == "missing" ? "" : ("; replaced output: " + why).c_str());
        } catch (const InputError& e) {
            ticker.end();
            ++totals.failedInput;
            std::fprintf(stderr, "penumbra: %s: failed (bad input): %s\n", tag.c_str(), oneLine(e.what()).c_str());
        } catch (const std::exception& e) {
            ticker.end();
            if (stopRequested()) {
                totals.notRun = mine.size() - n;
                std::fprintf(stderr, "penumbra: %s: interrupted, nothing written\n", tag.c_str());
                break;
            }
            ++totals.failedRuntime;
            std::fprintf(stderr, "penumbra: %s: failed: %s\n", tag.c_str(), oneLine(failureMessage(e)).c_str());
        }
    }

    printSummary(totals, mine.size(), all.size(), share, start, device);
    if (totals.failedInput > 0) return 2;
    if (totals.failedRuntime > 0 || stopRequested()) return 1;
    return 0;
}

}  // namespace penumbra
