// penumbra.Renderer: one scene document kept with a render session (session/render_session.h)
// so that renders with other overrides reuse the device, the uploaded scene where the
// overrides allow (batch/job_file.h, overridesShareSceneUpload) and the compiled pipelines.
#pragma once

#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "scene/load.h"
#include "session/render_session.h"

namespace penumbra::python {

// One --set override with its value already JSON: `override.value` is its text, for
// messages and for comparing overrides.
struct JsonOverride {
    Override override;
    nlohmann::json value;
};

class SceneRenderer {
public:
    // `document`: the scene, read or converted; `overrides` apply to every render, before
    // each render's own. Loads the scene (InputError), opens the device and uploads it.
    SceneRenderer(SceneDocument document, std::vector<JsonOverride> overrides, int deviceIndex);

    // Renders with `overrides` on top of the constructor's. Thread-safe: renders from
    // several threads take turns. `cancel` stops it (RenderSession::render).
    Image render(const std::vector<JsonOverride>& overrides, const std::atomic<bool>& cancel);

    // Pipelines created (each a driver compilation) and scenes uploaded so far.
    size_t kernelCompilations() const;
    size_t sceneUploads() const;
    std::string deviceName() const;

private:
    // The scene with the constructor's overrides and then `overrides`, and the list of all.
    std::pair<Scene, std::vector<Override>> load(const std::vector<JsonOverride>& overrides) const;

    SceneDocument m_document;
    std::vector<JsonOverride> m_overrides;
    mutable std::mutex m_mutex;  // one render at a time
    RenderSession m_session;
    std::optional<std::vector<Override>> m_prepared;  // the overrides of the scene prepared last
};

}  // namespace penumbra::python
