// Loading with overrides and choosing what to reuse (see scene_renderer.h).
#include "scene_renderer.h"

#include "batch/job_file.h"

namespace penumbra::python {

SceneRenderer::SceneRenderer(SceneDocument document, std::vector<JsonOverride> overrides, int deviceIndex)
    : m_document(std::move(document)), m_overrides(std::move(overrides)) {
    auto [scene, all] = load({});
    m_session.open(deviceIndex);
    m_session.prepare(scene, false);
    m_prepared = std::move(all);
}

std::pair<Scene, std::vector<Override>> SceneRenderer::load(const std::vector<JsonOverride>& overrides) const {
    SceneDocument document = m_document;
    std::vector<Override> all;
    for (const auto* list : {&m_overrides, &overrides})
        for (const JsonOverride& o : *list) {
            applyOverrideValue(document.doc, o.override, o.value);
            all.push_back(o.override);
        }
    return {buildScene(document), std::move(all)};
}

Image SceneRenderer::render(const std::vector<JsonOverride>& overrides, const std::atomic<bool>& cancel) {
    std::lock_guard lock(m_mutex);
    auto [scene, all] = load(overrides);
    const bool shares = m_prepared && overridesShareSceneUpload(*m_prepared, all);
    m_prepared.reset();  // until prepare succeeds
    m_session.prepare(scene, shares);
    m_prepared = std::move(all);
    return m_session.render({}, &cancel);
}

size_t SceneRenderer::kernelCompilations() const {
    std::lock_guard lock(m_mutex);
    return m_session.pipelinesCreated();
}

size_t SceneRenderer::sceneUploads() const {
    std::lock_guard lock(m_mutex);
    return m_session.uploads();
}

std::string SceneRenderer::deviceName() const { return m_session.context().info().name; }

}  // namespace penumbra::python
