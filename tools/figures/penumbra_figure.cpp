// penumbra_figure: the comparison figures of Veach's thesis and the lecture. Renders a scene
// once per value of one `direct` integrator option at equal spp, and a reference with `mis`
// and `solid_angle` at many more spp and another seed; prints each value's error against the
// reference and writes one PNG of the panels side by side, each labelled. One process, one
// Vulkan context, one Renderer (each value changes RenderParams or the specialized kernel:
// Renderer::retarget).
//
//   penumbra_figure SCENE --vary strategy|sphere_sampling|quad_sampling|triangle_sampling|heuristic [--values a,b,c]
//       [--spp N] [--reference-spp M] [--width W --height H] [--set PATH=VALUE]...
//       [--columns C] [--exposure E] [--exr-prefix P] [--device N] [--quiet] -o FIGURE.png
//
// stdout, one line per value: `VALUE relmse X rmse Y seconds Z` (compareImages against the
// reference; seconds of GPU rendering). Exit status as penumbra's: 2 bad usage or input, 1
// any other failure.
#include <unistd.h>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/exit_status.h"
#include "gpu/context.h"
#include "image/figure.h"
#include "image/image.h"
#include "render/renderer.h"
#include "scene/integrator_options.h"
#include "scene/load.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

const char* kUsage =
    "usage: penumbra_figure SCENE --vary strategy|sphere_sampling|quad_sampling|triangle_sampling|heuristic [--values "
    "a,b,c] [--spp N] "
    "[--reference-spp M] [--width W] [--height H] [--set PATH=VALUE]... [--columns C] [--exposure E] "
    "[--exr-prefix P] [--device N] [--quiet] -o FIGURE.png";

// The options that can be varied, their values in figure order (the defaults of --values),
// and the reference's value of each (the estimator with the lowest variance).
template <class E>
std::vector<std::string> valuesOf() {
    std::vector<const char*> names = allNames<E>();
    return {names.begin(), names.end()};
}
const std::map<std::string, std::vector<std::string>> kVaryValues = {
    {"strategy", valuesOf<Strategy>()},          {"sphere_sampling", valuesOf<SphereSampling>()},
    {"quad_sampling", valuesOf<QuadSampling>()}, {"triangle_sampling", valuesOf<TriangleSampling>()},
    {"heuristic", valuesOf<Heuristic>()},
};

struct Options {
    std::string scene, vary, output, exrPrefix;
    std::vector<std::string> values;
    std::vector<Override> overrides;
    long spp = -1, referenceSpp = -1, columns = -1;
    float exposure = 0.0f;
    int device = -1;
    bool quiet = false;
};

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> items;
    size_t start = 0;
    while (true) {
        size_t comma = text.find(',', start);
        items.push_back(text.substr(start, comma - start));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return items;
}

long parseInteger(const std::string& option, const std::string& text, long min) {
    char* end = nullptr;
    errno = 0;
    long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno != 0 || v < min || v > (1L << 30))
        throw InputError(option + ": expected an integer >= " + std::to_string(min) + ", got \"" + text + "\"");
    return v;
}
long parsePositive(const std::string& option, const std::string& text) { return parseInteger(option, text, 1); }

Options parseArguments(int argc, char** argv) {
    if (argc < 2) throw InputError(kUsage);
    Options o;
    std::string width, height;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) throw InputError(arg + ": missing value");
            return argv[++i];
        };
        if (arg == "--vary") o.vary = next();
        else if (arg == "--values") o.values = splitList(next());
        else if (arg == "--spp") o.spp = parsePositive(arg, next());
        else if (arg == "--reference-spp") o.referenceSpp = parsePositive(arg, next());
        else if (arg == "--width") width = std::to_string(parsePositive(arg, next()));
        else if (arg == "--height") height = std::to_string(parsePositive(arg, next()));
        else if (arg == "--set") o.overrides.push_back(parseOverride(next()));
        else if (arg == "--columns") o.columns = parsePositive(arg, next());
        else if (arg == "--exposure") {
            std::string v = next();
            char* end = nullptr;
            o.exposure = std::strtof(v.c_str(), &end);
            if (v.empty() || *end != '\0' || !std::isfinite(o.exposure))
                throw InputError("--exposure: expected a number, got \"" + v + "\"");
        } else if (arg == "--exr-prefix") o.exrPrefix = next();
        else if (arg == "--device") o.device = int(parseInteger(arg, next(), 0));
        else if (arg == "-o" || arg == "--output") o.output = next();
        else if (arg == "--quiet") o.quiet = true;
        else if (arg == "-h" || arg == "--help") {
            std::printf("%s\n", kUsage);
            std::exit(0);
        } else if (!arg.empty() && arg[0] == '-') throw InputError("unknown option " + arg);
        else if (o.scene.empty()) o.scene = arg;
        else throw InputError("unexpected argument \"" + arg + "\" (one scene per figure)");
    }
    if (o.scene.empty()) throw InputError("missing SCENE");
    if (o.output.empty()) throw InputError("missing -o FIGURE.png");
    auto known = kVaryValues.find(o.vary);
    if (known == kVaryValues.end())
        throw InputError("--vary: unknown option \"" + o.vary +
                         "\" (strategy, sphere_sampling, quad_sampling, triangle_sampling or heuristic)");
    if (o.values.empty()) o.values = known->second;
    for (const std::string& v : o.values) {
        bool ok = false;
        for (const std::string& k : known->second) ok = ok || v == k;
        if (!ok) {
            std::string list;
            for (const std::string& k : known->second) list += (list.empty() ? "" : ", ") + k;
            throw InputError("--values: unknown " + o.vary + " \"" + v + "\" (" + list + ")");
        }
    }
    if (!width.empty()) o.overrides.push_back({"film.width", width});
    if (!height.empty()) o.overrides.push_back({"film.height", height});
    return o;
}

// Fails before rendering (exit 1) when a file cannot be written, instead of after it.
void checkWritableDirectory(const fs::path& file) {
    fs::path dir = file.parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::is_directory(dir, ec) || access(dir.c_str(), W_OK) != 0)
        throw std::runtime_error("cannot write " + file.string() + ": directory " + dir.string() +
                                 " does not exist or is not writable");
}

// "0.0123", "1.23e-05": three significant digits.
std::string formatError(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", x);
    return text;
}

int run(const Options& o) {
    // Load every variant first: bad input fails before anything is rendered or printed.
    std::vector<Override> base = o.overrides;
    if (o.spp > 0) base.push_back({"sampler.spp", std::to_string(o.spp)});
    std::vector<Scene> scenes;
    for (const std::string& value : o.values) {
        std::vector<Override> overrides = base;
        overrides.push_back({"integrator." + o.vary, value});
        scenes.push_back(loadScene(o.scene, overrides));
        if (scenes.back().integrator.type != IntegratorType::Direct)
            throwInputError(o.scene, "integrator.type", "--vary needs the direct integrator");
    }
    const SamplerSettings& sampler = scenes[0].sampler;
    std::vector<Override> refOverrides = o.overrides;
    refOverrides.push_back({"integrator.strategy", toName(Strategy::Mis)});
    refOverrides.push_back({"integrator.sphere_sampling", toName(SphereSampling::SolidAngle)});
    refOverrides.push_back({"integrator.quad_sampling", toName(QuadSampling::SolidAngle)});
    refOverrides.push_back({"integrator.triangle_sampling", toName(TriangleSampling::SolidAngle)});
    refOverrides.push_back(
        {"sampler.spp", std::to_string(o.referenceSpp > 0 ? uint64_t(o.referenceSpp) : 64ull * sampler.spp)});
    refOverrides.push_back({"sampler.seed", std::to_string(uint64_t(sampler.seed) + 1)});
    Scene reference = loadScene(o.scene, refOverrides);

    checkWritableDirectory(o.output);
    if (!o.exrPrefix.empty()) checkWritableDirectory(o.exrPrefix + "reference.exr");
    for (const std::string& note : scenes[0].notes)
        if (!o.quiet) std::fprintf(stderr, "penumbra_figure: %s\n", note.c_str());

    gpu::ContextOptions contextOptions;
    contextOptions.deviceIndex = o.device;
    gpu::Context context(contextOptions);

    // The reference first: it also compiles the kernel (lazily, on the first dispatch on
    // lavapipe), which would otherwise count against the first value's time.
    using Clock = std::chrono::steady_clock;
    Renderer renderer(context, reference);
    auto render = [&](const Scene& scene, const std::string& what) {
        if (!o.quiet) std::fprintf(stderr, "penumbra_figure: %s, %u spp\n", what.c_str(), scene.sampler.spp);
        renderer.retarget(scene);
        renderer.compileKernel();  // a new option may mean a new kernel: compiling is not rendering
        auto t0 = Clock::now();
        renderer.renderAll();
        double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        return renderer.readback(seconds);
    };
    Image referenceImage = render(reference, "reference (mis, solid_angle)");
    if (!o.exrPrefix.empty()) writeExr(o.exrPrefix + "reference.exr", referenceImage);

    std::vector<Image> images;
    images.reserve(scenes.size());
    std::vector<FigurePanel> panels;
    for (size_t i = 0; i < scenes.size(); ++i) {
        images.push_back(render(scenes[i], o.vary + " " + o.values[i]));
        const Image& image = images.back();
        CompareMetrics m = compareImages(image, referenceImage, o.values[i], "reference");
        std::printf("%s relmse %.6g rmse %.6g seconds %.3f\n", o.values[i].c_str(), m.relmse, m.rmse,
                    *image.meta.renderSeconds);
        std::fflush(stdout);
        panels.push_back({&image, o.values[i] + "  " + std::to_string(scenes[i].sampler.spp) + " spp  relMSE " +
                                      formatError(m.relmse)});
        if (!o.exrPrefix.empty()) writeExr(o.exrPrefix + o.values[i] + ".exr", image);
    }
    Rgb8Image figure = composeFigure(panels, o.columns > 0 ? uint32_t(o.columns) : uint32_t(panels.size()), o.exposure);
    writePngRgb8(o.output, figure.width, figure.height, figure.rgb);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return runReportingErrors("penumbra_figure", [&] { return run(parseArguments(argc, argv)); });
}
