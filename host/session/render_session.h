// The device side of a process that renders one scene after another (penumbra batch, the
// Python module's Renderer; penumbra render is the case of one): the Vulkan context, the
// pipeline cache and a renderer holding the last scene uploaded, reused when the next
// scene shares it. Deciding that two scenes share an upload is the caller's (batch/job_file.h).
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>

#include "gpu/context.h"
#include "gpu/kernel_cache.h"
#include "image/image.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace penumbra {

class RenderSession {
public:
    RenderSession() = default;
    RenderSession(const RenderSession&) = delete;
    RenderSession& operator=(const RenderSession&) = delete;

    // Creates the context on first use (deviceIndex -1: PENUMBRA_DEVICE or the automatic
    // choice, gpu/context.h); throws when there is no device. Later calls do nothing.
    void open(int deviceIndex);
    bool isOpen() const { return m_context.has_value(); }

    // Makes `scene` the next render. When `sharesUpload` (the caller knows that `scene`
    // differs from the uploaded one only in camera, sampler and integrator settings:
    // batch/job_file.h), a renderer holds a scene, and light_selection and the film size
    // agree, the renderer is retargeted: only the render parameters are uploaded. Otherwise
    // the scene is uploaded anew; its pipeline still comes from the cache when its kernel
    // options match an earlier scene's (gpu/kernel_cache.h). Then the driver compiles the
    // kernel (Renderer::compileKernel), so that render() times the passes alone. True when
    // the upload was reused.
    bool prepare(const Scene& scene, bool sharesUpload);

    // Renders the prepared scene to its spp and reads it back; penumbra:render_seconds is
    // the passes' time (docs/design/contract-decisions.md, "render_seconds"). `cancel` stops it within a submission
    // (std::runtime_error "render interrupted"). After any failure the renderer is dropped,
    // its state unknown, so that the next prepare uploads anew.
    Image render(const std::function<void(const RenderProgress&)>& progress = {},
                 const std::atomic<bool>* cancel = nullptr);

    // Pipelines the cache created (each a driver compilation) and reused; 0 before open().
    size_t pipelinesCreated() const { return m_kernels ? m_kernels->pipelinesCreated() : 0; }
    size_t pipelinesReused() const { return m_kernels ? m_kernels->pipelinesReused() : 0; }
    // Scenes uploaded anew and retargeted by prepare().
    size_t uploads() const { return m_uploads; }
    size_t uploadsReused() const { return m_uploadsReused; }

    // The scene the renderer holds, if any (none before prepare() and after a failure).
    const Scene* uploadedScene() const { return m_renderer ? &m_renderer->scene() : nullptr; }

    // The context; open() first.
    const gpu::Context& context() const { return *m_context; }

private:
    // Declaration order is teardown order in reverse: renderer, then cache, then context.
    std::optional<gpu::Context> m_context;
    std::optional<gpu::KernelCache> m_kernels;
    std::unique_ptr<Renderer> m_renderer;
    size_t m_uploads = 0, m_uploadsReused = 0;
};

}  // namespace penumbra
