// Reuse of the context, pipelines and upload across renders (see render_session.h).
#include "session/render_session.h"

#include <chrono>
#include <stdexcept>

#include "scene/integrator_options.h"

namespace penumbra {

void RenderSession::open(int deviceIndex) {
    if (m_context) return;
    gpu::ContextOptions options;
    options.deviceIndex = deviceIndex;
    m_context.emplace(options);
    m_kernels.emplace(*m_context);
}

bool RenderSession::prepare(const Scene& scene, bool sharesUpload) {
    if (!m_context) throw std::logic_error("RenderSession::prepare before open");
    // Renderer::retarget keeps the light tables and the accumulation buffer: light_selection
    // and the film size must agree as well.
    const bool reuse = sharesUpload && m_renderer &&
                       !needsNewUpload(m_renderer->scene().integrator, scene.integrator) &&
                       m_renderer->scene().film.width == scene.film.width &&
                       m_renderer->scene().film.height == scene.film.height;
    try {
        if (reuse) {
            m_renderer->retarget(scene);
        } else {
            m_renderer.reset();  // free the previous scene's device memory first
            m_renderer = std::make_unique<Renderer>(*m_context, scene, &*m_kernels);
        }
        m_renderer->compileKernel();  // start-up, not rendering
    } catch (...) {
        m_renderer.reset();  // state unknown
        throw;
    }
    ++(reuse ? m_uploadsReused : m_uploads);
    return reuse;
}

Image RenderSession::render(const std::function<void(const RenderProgress&)>& progress,
                            const std::atomic<bool>* cancel) {
    if (!m_renderer) throw std::logic_error("RenderSession::render before prepare");
    using Clock = std::chrono::steady_clock;
    try {
        const auto start = Clock::now();
        m_renderer->renderAll(progress, cancel);
        return m_renderer->readback(std::chrono::duration<double>(Clock::now() - start).count());
    } catch (...) {
        m_renderer.reset();  // state unknown after a failed or interrupted render
        throw;
    }
}

}  // namespace penumbra
