// Job file parsing for penumbra batch: validation with JSON paths (JsonReader), sweep
// expansion and output-name placeholders (docs/BATCH.md, "Job files").
#include "batch/job_file.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>

#include "core/errors.h"
#include "core/input_file.h"
#include "image/output_format.h"
#include "scene/json_reader.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The most jobs a job file may expand to, over all its entries: a million jobs take about
// 1 GB to hold and list; a larger study is several job files.
constexpr size_t kMaxJobs = 1000000;

struct SweepAxis {
    std::string path;
    std::vector<json> values;
};

// "PATH=VALUE" or {PATH: VALUE}: the overrides of a "set" member, paths checked now.
std::vector<Override> readSet(const JsonReader& set) {
    std::vector<Override> result;
    auto checked = [&](const JsonReader& where, const std::string& text) {
        try {
            return parseOverride(text);
        } catch (const InputError& e) {
            where.fail(e.what());
        }
    };
    if (set.json().is_object()) {
        for (auto it = set.json().begin(); it != set.json().end(); ++it) {
            JsonReader value = set.at(it.key().c_str());
            // The value stays JSON: dumped here, parsed again by applyOverride.
            result.push_back(checked(value, it.key() + "=" + it.value().dump()));
        }
    } else if (set.json().is_array()) {
        for (size_t i = 0; i < set.size(); ++i) result.push_back(checked(set[i], set[i].string()));
    } else {
        set.fail("expected an object {\"PATH\": VALUE, ...} or an array [\"PATH=VALUE\", ...]");
    }
    return result;
}

SweepAxis readAxis(const JsonReader& axis) {
    axis.expectKeys({"path", "values"}, "sweep");
    SweepAxis result;
    result.path = axis.at("path").string();
    try {
        parseOverride(result.path + "=0");
    } catch (const InputError& e) {
        axis.at("path").fail(e.what());
    }
    JsonReader values = axis.at("values");
    if (values.size() == 0) values.fail("a sweep needs at least one value");
    for (size_t i = 0; i < values.size(); ++i) result.values.push_back(values[i].json());
    return result;
}

std::vector<SweepAxis> readSweep(const JsonReader& sweep) {
    std::vector<SweepAxis> axes;
    if (sweep.json().is_object()) {
        axes.push_back(readAxis(sweep));
    } else if (sweep.json().is_array()) {
        if (sweep.size() == 0) sweep.fail("a sweep needs at least one {\"path\", \"values\"} object");
        for (size_t i = 0; i < sweep.size(); ++i) {
            axes.push_back(readAxis(sweep[i]));
            for (size_t k = 0; k < i; ++k)
                if (axes[k].path == axes[i].path) sweep[i].at("path").fail("\"" + axes[i].path + "\" is swept twice");
        }
    } else {
        sweep.fail("expected {\"path\": PATH, \"values\": [...]} or an array of them (a cartesian product)");
    }
    return axes;
}

// A sweep value as part of a file name: strings as written, numbers and booleans as JSON,
// arrays joined with '_'; then every character outside [A-Za-z0-9._+-] becomes '_'.
std::string fileNamePart(const json& value) {
    std::string text;
    if (value.is_string()) {
        text = value.get<std::string>();
    } else if (value.is_array()) {
        for (size_t i = 0; i < value.size(); ++i) {
            if (i) text += '_';
            text += fileNamePart(value[i]);
        }
    } else {
        text = value.dump();
    }
    for (char& c : text)
        if (!std::isalnum((unsigned char)c) && c != '.' && c != '_' && c != '+' && c != '-') c = '_';
    // "" and dots alone would make a name that is no name ("out/.exr") or leaves its folder
    // ("out/{value}/a.exr" with ".."): such a value is written as underscores.
    if (text.find_first_not_of('.') == std::string::npos) text = std::string(std::max<size_t>(text.size(), 1), '_');
    return text;
}

// Expands {i}, {i:0N}, {value} and {PATH} in an output pattern; {{ and }} are literal braces.
// Fails at `where` on anything else, so that a typo never silently names files.
std::string expandPattern(const JsonReader& where, const std::string& pattern, size_t index,
                          const std::vector<SweepAxis>& axes, const std::vector<size_t>& choice) {
    const std::string forms = "use {i}, {i:04}, {value} (one swept path) or {PATH} (a swept path)";
    std::string out;
    for (size_t k = 0; k < pattern.size(); ++k) {
        char c = pattern[k];
        if (c == '}') {
            if (k + 1 < pattern.size() && pattern[k + 1] == '}') {
                out += '}';
                ++k;
                continue;
            }
            where.fail("unmatched '}' in \"" + pattern + "\" (write }} for a literal brace)");
        }
        if (c != '{') {
            out += c;
            continue;
        }
        if (k + 1 < pattern.size() && pattern[k + 1] == '{') {
            out += '{';
            ++k;
            continue;
        }
        size_t close = pattern.find('}', k);
        if (close == std::string::npos) where.fail("unmatched '{' in \"" + pattern + "\" (write {{ for a literal brace)");
        std::string name = pattern.substr(k + 1, close - k - 1);
        k = close;
        if (name == "i") {
            out += std::to_string(index);
        } else if (name.rfind("i:", 0) == 0) {
            std::string spec = name.substr(2);
            // {i:0N} with N = 1..99 (docs/BATCH.md): {i:00} pads to no width at all.
            bool ok = spec.size() >= 2 && spec.size() <= 3 && spec[0] == '0' &&
                      std::all_of(spec.begin(), spec.end(), [](unsigned char d) { return std::isdigit(d); }) &&
                      std::stoul(spec.substr(1)) >= 1;
            if (!ok) where.fail("bad placeholder {" + name + "} in \"" + pattern + "\": " + forms);
            std::string digits = std::to_string(index);
            size_t width = size_t(std::stoul(spec.substr(1)));
            out += std::string(width > digits.size() ? width - digits.size() : 0, '0') + digits;
        } else if (name == "value") {
            if (axes.size() != 1)
                where.fail("{value} in \"" + pattern + "\" needs a sweep of exactly one path; name the path, e.g. {" +
                           (axes.empty() ? std::string("camera.eye") : axes[0].path) + "}");
            out += fileNamePart(axes[0].values[choice[0]]);
        } else {
            auto it = std::find_if(axes.begin(), axes.end(), [&](const SweepAxis& a) { return a.path == name; });
            if (it == axes.end()) where.fail("unknown placeholder {" + name + "} in \"" + pattern + "\": " + forms);
            out += fileNamePart(it->values[choice[size_t(it - axes.begin())]]);
        }
    }
    return out;
}

bool hasExtension(const std::string& name, const std::string& ext) {
    std::string e = fs::path(name).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e == ext;
}

// `name` relative to the job file's folder `base`; unless any path is allowed, it must
// lie inside that folder, as a glTF model's URIs must lie inside the model's (docs/design/contract-decisions.md,
// "Job files and their folder"): a job file from elsewhere cannot read or replace files
// anywhere on the disk, nor create folders there.
fs::path resolve(const JsonReader& where, const fs::path& base, const std::string& name) {
    fs::path p(name);
    fs::path resolved = (p.is_absolute() ? p : base / p).lexically_normal();
    if (!allowAnyPath() && !isInsideFolder(resolved, base))
        where.fail("refusing to use \"" + name +
                   "\": it is outside the job file's folder (--allow-any-path allows it)");
    return resolved;
}

}  // namespace

std::vector<BatchJob> loadJobFile(const fs::path& file) {
    const std::string label = file.string();
    const json doc = readJsonFile(file, label);
    const fs::path base = file.parent_path();
    JsonReader root(doc, label);

    std::vector<Override> common;
    std::optional<JsonReader> list;
    if (doc.is_array()) {
        list = root;
    } else if (doc.is_object()) {
        root.expectKeys({"jobs", "set"}, "a job file");
        if (auto set = root.find("set")) common = readSet(*set);
        list = root.at("jobs");
        list->size();  // fails unless an array
    } else {
        root.fail("expected {\"jobs\": [...]} or an array of jobs");
    }

    // Every entry is read and its jobs counted before any is expanded, so that a file past
    // the limit is refused at once (8 entries of a million values once took 8 GB and two
    // minutes to refuse). The count is checked at each factor, so that the product of the
    // axes cannot wrap (64 axes of 2 values once made 2^64 = 0 jobs, and batch exited 0).
    struct Entry {
        JsonReader entry, outputAt;
        std::string scene, output, png;
        std::optional<JsonReader> pngAt;
        std::vector<Override> set;
        std::vector<SweepAxis> axes;
        size_t count = 1;
    };
    std::vector<Entry> entries;
    size_t total = 0;
    for (size_t j = 0; j < list->size(); ++j) {
        JsonReader entry = (*list)[j];
        entry.expectKeys({"scene", "output", "png", "set", "sweep"}, "job");
        const std::string scene = entry.at("scene").string();
        if (scene.empty()) entry.at("scene").fail("empty file name");
        JsonReader outputAt = entry.at("output");
        const std::string output = outputAt.string();
        const std::optional<OutputFormat> format = outputFormatOf(output);
        if (!format) outputAt.fail(outputFormatProblem(output));
        std::vector<Override> set = common;
        if (auto own = entry.find("set")) {
            auto more = readSet(*own);
            set.insert(set.end(), more.begin(), more.end());
        }
        std::optional<JsonReader> pngAt = entry.find("png");
        std::string png;
        // An output ending in .png is the PNG alone (SCENE_FORMAT.md "Output"), as for render -o.
        if (pngAt && *format == OutputFormat::Png)
            pngAt->fail("the output \"" + output + "\" is a PNG already; give \"png\" only with an .exr output");
        if (pngAt && pngAt->json().is_boolean()) {
            // true: the output's name with .png
            if (pngAt->boolean()) png = fs::path(output).replace_extension(".png").string();
        } else if (pngAt) {
            png = pngAt->string();
            if (!hasExtension(png, ".png")) pngAt->fail("\"" + png + "\" does not end in .png");
        }
        std::vector<SweepAxis> axes;
        if (auto sweep = entry.find("sweep")) axes = readSweep(*sweep);

        size_t count = 1;
        for (const SweepAxis& a : axes) {
            count *= a.values.size();
            if (count > kMaxJobs - total) break;
        }
        if (count > kMaxJobs - total)
            (axes.empty() ? entry : entry.at("sweep"))
                .fail("the job file expands to more than " + std::to_string(kMaxJobs) + " jobs");
        total += count;
        entries.push_back({entry, outputAt, scene, output, png, pngAt, std::move(set), std::move(axes), count});
    }

    std::vector<BatchJob> jobs;
    jobs.reserve(total);
    std::map<fs::path, std::string> writers;  // every output file -> the job that writes it
    for (const Entry& e : entries) {
        const auto& [entry, outputAt, scene, output, png, pngAt, set, axes, count] = e;
        // Cartesian product in row-major order: the last axis varies fastest.
        std::vector<size_t> choice(axes.size(), 0);
        for (size_t index = 0; index < count; ++index) {
            size_t rest = index;
            for (size_t a = axes.size(); a-- > 0;) {
                choice[a] = rest % axes[a].values.size();
                rest /= axes[a].values.size();
            }
            BatchJob job;
            job.scene = resolve(entry.at("scene"), base, scene);
            job.output = resolve(outputAt, base, expandPattern(outputAt, output, index, axes, choice));
            if (pngAt && !png.empty()) job.png = resolve(*pngAt, base, expandPattern(*pngAt, png, index, axes, choice));
            job.overrides = set;
            job.origin = entry.path();
            std::string values;
            for (size_t a = 0; a < axes.size(); ++a) {
                const json& v = axes[a].values[choice[a]];
                job.overrides.push_back({axes[a].path, v.dump()});
                values += (a ? ", " : "") + axes[a].path + "=" + v.dump();
            }
            if (!axes.empty()) job.origin += " sweep " + std::to_string(index) + " (" + values + ")";

            for (const fs::path* target : {&job.output, &job.png}) {
                if (target->empty()) continue;
                auto [it, fresh] = writers.emplace(*target, job.origin);
                if (!fresh)
                    (target == &job.output ? outputAt : *pngAt)
                        .fail("\"" + target->string() + "\" is written by two jobs: " + it->second + " and " +
                              job.origin + (axes.empty() ? "" : "; name sweep outputs with {i} or {value}"));
            }
            jobs.push_back(std::move(job));
        }
    }
    return jobs;
}

std::string overrideSection(const std::string& path) { return path.substr(0, path.find_first_of(".[")); }

bool overridesShareSceneUpload(const std::vector<Override>& previous, const std::vector<Override>& next) {
    auto uploaded = [](const std::vector<Override>& overrides) {
        std::vector<std::pair<std::string, std::string>> kept;
        for (const Override& o : overrides) {
            std::string section = overrideSection(o.path);
            if (section != "camera" && section != "sampler" && section != "integrator") kept.emplace_back(o.path, o.value);
        }
        return kept;
    };
    return uploaded(previous) == uploaded(next);
}

}  // namespace penumbra
