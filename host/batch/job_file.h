// Job files of `penumbra batch` (docs/BATCH.md): a list of renders, each a scene file with
// --set style overrides and an output, where a sweep expands to one job per value (or per
// combination of values). Reading and validating only; running the jobs is
// cli/batch_command.cpp's.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/load.h"

namespace penumbra {

struct BatchJob {
    std::filesystem::path scene;   // resolved against the job file's directory
    std::filesystem::path output;  // EXR, resolved likewise, placeholders expanded
    std::filesystem::path png;     // empty: no PNG
    // Applied in order: the file's "set", the job's "set", then the sweep's values.
    std::vector<Override> overrides;
    // Where the job comes from, for messages: "jobs[2]" or "jobs[2] sweep 5 (camera.eye=[1,1,5])".
    std::string origin;
};

// Reads a job file and expands its sweeps, in file order (a sweep's last path varies
// fastest). Every problem with the file itself (syntax, types, unknown keys, malformed
// override paths, bad placeholders, two jobs writing one file) throws InputError
// "<file>: <json path>: why", so that nothing runs. Problems with the scenes it names are
// found when each job runs.
std::vector<BatchJob> loadJobFile(const std::filesystem::path& file);

// For renders of one scene document already read (the Python module's Renderer): whether
// `next` keeps the upload of `previous`, i.e. the same overrides once those of camera.*,
// sampler.* and integrator.* are left out, in the same order. (Batch jobs compare the loaded
// scenes instead, scene.h sharesUpload, since a scene file may change between jobs.)
bool overridesShareSceneUpload(const std::vector<Override>& previous, const std::vector<Override>& next);

// The root key of an override path: "camera" for "camera.eye", "lights" for "lights[0].power".
std::string overrideSection(const std::string& path);

}  // namespace penumbra
