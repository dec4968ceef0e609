// The preview loop (see preview_loop.h): window, device and frames; input becomes camera
// and integrator changes that restart the accumulation.
#ifdef PENUMBRA_HAVE_GLFW
#include "preview/preview_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "gpu/context.h"
#include "gpu/vk_check.h"
#include "image/image.h"
#include "preview/camera_controller.h"
#include "preview/integrator_controls.h"
#include "preview/layer_cycle.h"
#include "preview/pass_scheduler.h"
#include "preview/swapchain.h"
#include "preview/tone_mapper.h"
#include "preview/window.h"
#include "render/renderer.h"
#include "scene/integrator_options.h"

namespace penumbra::preview {
namespace {

using Clock = std::chrono::steady_clock;
using gpu::vkCheck;

constexpr double kTargetFrameSeconds = 0.040;  // work per frame the adaptive budget aims at
constexpr double kTitleSeconds = 0.25;         // how often the title's numbers change
constexpr float kExposureStep = 0.5f;          // stops per +/- press
constexpr uint32_t kMinWindowSide = 256;       // tiny films are shown magnified

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// One frame's command buffer, fence and acquire semaphore. One frame is in flight at a
// time: the loop waits for each (which also times it), so these are reused every frame.
class FrameResources {
public:
    explicit FrameResources(const gpu::Context& context) : m_context(context) {
        VkDevice device = context.device();
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = context.commandPool();
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        vkCheck(vkAllocateCommandBuffers(device, &alloc, &cmd), "allocate the preview's command buffer");
        VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        try {
            vkCheck(vkCreateFence(device, &fenceInfo, nullptr, &fence), "create the preview's frame fence");
            vkCheck(vkCreateSemaphore(device, &semaphoreInfo, nullptr, &acquired),
                    "create the preview's acquire semaphore");
        } catch (...) {
            this->~FrameResources();
            throw;
        }
    }
    ~FrameResources() {
        VkDevice device = m_context.device();
        vkDeviceWaitIdle(device);
        if (acquired) vkDestroySemaphore(device, acquired, nullptr);
        if (fence) vkDestroyFence(device, fence, nullptr);
        if (cmd) vkFreeCommandBuffers(device, m_context.commandPool(), 1, &cmd);
        acquired = VK_NULL_HANDLE;
        fence = VK_NULL_HANDLE;
        cmd = VK_NULL_HANDLE;
    }
    FrameResources(const FrameResources&) = delete;
    FrameResources& operator=(const FrameResources&) = delete;

    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    VkSemaphore acquired = VK_NULL_HANDLE;

private:
    const gpu::Context& m_context;
};

// A window showing the film 1:1, magnified to at least kMinWindowSide, shrunk to the screen.
VkExtent2D initialWindowSize(uint32_t width, uint32_t height, VkExtent2D workArea) {
    double scale = 1.0;
    const uint32_t longest = std::max(width, height);
    if (longest < kMinWindowSide) scale = std::ceil(double(kMinWindowSide) / longest);
    if (workArea.width > 0 && workArea.height > 0)
        scale = std::min({scale, 0.95 * workArea.width / width, 0.9 * workArea.height / height});
    return {std::max(1u, uint32_t(std::lround(width * scale))), std::max(1u, uint32_t(std::lround(height * scale)))};
}

// The film scaled uniformly to fit `window`, centred (the rest is cleared).
void fitFilm(uint32_t width, uint32_t height, VkExtent2D window, VkOffset2D& offset, VkExtent2D& size) {
    double scale = std::min(double(window.width) / width, double(window.height) / height);
    size.width = std::clamp(uint32_t(std::lround(width * scale)), 1u, window.width);
    size.height = std::clamp(uint32_t(std::lround(height * scale)), 1u, window.height);
    offset.x = int32_t((window.width - size.width) / 2);
    offset.y = int32_t((window.height - size.height) / 2);
}

class Preview {
public:
    Preview(const Scene& scene, const PreviewSettings& settings);
    void run();

private:
    // Applies one input event; returns false for quit.
    bool handle(const InputEvent& event);
    void frame(bool render);
    void fitSwapchain();
    uint64_t recordPasses(VkCommandBuffer cmd, bool render);
    void recordPresentation(VkCommandBuffer cmd, VkImage target);
    double submitAndPresent(VkCommandBuffer cmd, std::optional<uint32_t> image);
    void save();
    void updateTitle(bool force);
    void restart();
    void rebuildRenderer();

    const Scene& m_scene;
    const PreviewSettings& m_settings;
    GlfwSession m_glfw;
    std::optional<Window> m_window;
    std::optional<gpu::Context> m_context;
    std::optional<Renderer> m_renderer;
    std::optional<Swapchain> m_swapchain;
    std::optional<ToneMapper> m_toneMapper;
    std::optional<FrameResources> m_frame;
    LayerCycle m_layers;       // the A key: rgb or one of film.aovs
    bool m_layerStale = true;  // the shown AOV's picture predates the sums

    PassScheduler m_scheduler;
    CameraController m_camera;
    IntegratorSettings m_integrator;
    float m_exposure = 0.0f;
    uint64_t m_rowBudget = 0;
    uint32_t m_frameNumber = 0;
    bool m_cameraChanged = false, m_integratorChanged = false;
    bool m_recreateSwapchain = false;
    bool m_notedAo = false;
    bool m_notedNoLayers = false;
    bool m_titleDirty = false;

    Clock::time_point m_restartTime = Clock::now();
    Clock::time_point m_titleTime = Clock::now();
    uint64_t m_titleSamples = 0;  // pixel samples since m_titleTime
    double m_rate = 0.0;          // pixel samples per second, for the title
};

Preview::Preview(const Scene& scene, const PreviewSettings& settings)
    : m_scene(scene),
      m_settings(settings),
      m_layers(scene.film.aovs),
      m_scheduler(scene.film.height, scene.sampler.spp),
      m_camera(scene.camera),
      m_integrator(scene.integrator),
      m_exposure(settings.look.exposure) {  // --exposure: where the +/- keys start
    const uint32_t width = scene.film.width, height = scene.film.height;
    VkExtent2D size = initialWindowSize(width, height, m_glfw.workArea());
    m_window.emplace("penumbra preview: " + scene.name, int(size.width), int(size.height));

    gpu::ContextOptions options;
    options.deviceIndex = settings.deviceIndex;
    options.instanceExtensions = m_glfw.requiredInstanceExtensions();
    options.createSurface = [this](VkInstance instance) { return m_window->createSurface(instance); };
    m_context.emplace(options);
    m_renderer.emplace(*m_context, scene);
    m_swapchain.emplace(*m_context, m_window->framebufferSize());
    m_toneMapper.emplace(*m_context, m_renderer->accumulation(), m_renderer->accumulationCompensation(), width, height,
                         m_swapchain->isSrgb());
    m_frame.emplace(*m_context);
    m_rowBudget = settings.rowsPerFrame > 0 ? settings.rowsPerFrame : std::min<uint64_t>(height, 64);
}

void Preview::run() {
    size_t nextScript = 0;
    const auto& script = m_settings.script;
    bool quit = false;
    updateTitle(true);
    while (!quit && !m_window->shouldClose()) {
        VkExtent2D framebuffer = m_window->framebufferSize();
        if (framebuffer.width == 0 || framebuffer.height == 0) {
            m_window->waitEvents();  // minimised: nothing to show, nothing to spin for
            continue;
        }
        // Converged and nobody is counting frames or waiting for scripted ones: sleep
        // until the window system has something for us.
        const bool idle = m_scheduler.finished() && m_settings.frames == 0 && nextScript >= script.size();
        if (idle) m_window->waitEvents();
        else m_window->pollEvents();
        std::vector<InputEvent> events = m_window->takeEvents();
        bool redraw = m_window->takeRedrawRequest();
        const bool resized = m_swapchain->extent().width != framebuffer.width ||
                             m_swapchain->extent().height != framebuffer.height;
        if (idle && events.empty() && !redraw && !resized && !m_recreateSwapchain) continue;

        ++m_frameNumber;
        while (nextScript < script.size() && script[nextScript].frame <= m_frameNumber)
            events.push_back(script[nextScript++].event);
        for (const InputEvent& event : events)
            if (!handle(event)) quit = true;
        if (quit) break;
        if (m_cameraChanged) m_renderer->setCamera(m_camera.camera());
        if (m_integratorChanged) {
            if (needsNewUpload(m_integrator, m_renderer->scene().integrator)) rebuildRenderer();
            else m_renderer->setIntegrator(m_integrator);
        }
        if (m_cameraChanged || m_integratorChanged) restart();
        m_cameraChanged = m_integratorChanged = false;

        frame(!m_scheduler.finished());
        if (m_settings.frames > 0 && m_frameNumber >= m_settings.frames) break;
    }

    // With an AOV shown, the pixels already hold what the window shows: its picture of all
    // the samples so far (frame() renews it after each frame's passes).
    if (!m_settings.screenshot.empty() && m_layers.showsRgb()) {
        // What the window shows, at the film's resolution: tone-map the accumulation as it
        // stands (with the current exposure) and copy it to the host once.
        m_context->submitAndWait([&](VkCommandBuffer cmd) {
            // Shader and transfer writes of earlier submissions -> the tone map's reads.
            VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
            barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
            barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
            m_toneMapper->record(cmd, {m_exposure, m_settings.look.curve});
            // The tone map's pixel writes -> the host's read of them after the wait.
            VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
            toHost.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
            toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost,
                                 0, nullptr, 0, nullptr);
        });
    }
    if (!m_settings.screenshot.empty()) {
        writePngRgb8(m_settings.screenshot, m_toneMapper->width(), m_toneMapper->height(), m_toneMapper->readRgb());
    }
    if (!m_settings.quiet)
        std::fprintf(stderr, "preview: %u/%u spp\n", m_scheduler.samplesDone(), m_scheduler.spp());
}

bool Preview::handle(const InputEvent& event) {
    // The height of the film on screen, in the screen coordinates drags are measured in.
    const double viewHeight = [&] {
        VkOffset2D offset;
        VkExtent2D size;
        VkExtent2D window = m_window->size();
        if (window.width == 0 || window.height == 0) return 0.0;
        fitFilm(m_scene.film.width, m_scene.film.height, window, offset, size);
        return double(size.height);
    }();
    switch (event.type) {
        case InputEvent::Type::Drag:
            if (event.button == MouseButton::Left) m_camera.orbit(event.dx, event.dy, viewHeight);
            else m_camera.pan(event.dx, event.dy, viewHeight);
            m_cameraChanged = true;
            return true;
        case InputEvent::Type::Scroll:
            m_camera.zoom(event.dy);
            m_cameraChanged = true;
            return true;
        case InputEvent::Type::Resize:
            m_window->setSize(event.width, event.height);
            return true;
        case InputEvent::Type::Key: break;
    }
    switch (event.action) {
        case Action::Quit: return false;
        case Action::ResetCamera:
            m_camera.reset();
            m_cameraChanged = true;
            return true;
        case Action::ExposureUp:
            m_exposure += kExposureStep;
            m_titleDirty = true;
            return true;
        case Action::ExposureDown:
            m_exposure -= kExposureStep;
            m_titleDirty = true;
            return true;
        case Action::Save: save(); return true;
        case Action::CycleLayer:
            if (m_layers.next()) {
                m_layerStale = true;
                m_titleDirty = true;
            } else if (!m_notedNoLayers && !m_settings.quiet) {
                std::fprintf(stderr, "preview: this scene has no AOV layers to show (film.aovs, --aov)\n");
                m_notedNoLayers = true;
            }
            return true;
        default: break;
    }
    if (applyIntegratorAction(m_integrator, event.action)) {
        m_integratorChanged = true;
    } else if (isIntegratorAction(event.action) && m_integrator.type != IntegratorType::Direct && !m_notedAo) {
        if (!m_settings.quiet)
            std::fprintf(stderr, "preview: strategy keys apply to the direct integrator; this scene uses ao\n");
        m_notedAo = true;
    }
    return true;
}

// Light selection is built into the light tables with the scene (Renderer::setIntegrator
// refuses to change it): a new Renderer for the scene under the current integrator and
// camera, and a tone mapper that reads its accumulation.
void Preview::rebuildRenderer() {
    vkDeviceWaitIdle(m_context->device());
    Scene scene = m_scene;
    scene.integrator = m_integrator;
    scene.camera = m_camera.camera();
    m_toneMapper.reset();
    m_renderer.reset();
    m_renderer.emplace(*m_context, scene);
    m_toneMapper.emplace(*m_context, m_renderer->accumulation(), m_renderer->accumulationCompensation(),
                         m_scene.film.width, m_scene.film.height, m_swapchain->isSrgb());
}

void Preview::restart() {
    m_renderer->reset();
    m_scheduler.restart();
    m_restartTime = Clock::now();
    updateTitle(true);
}

// One frame: the swapchain fitted to the window, this frame's passes (when `render`), the
// tone map (or the shown AOV's picture) and, when an image was acquired, its presentation;
// then the row budget and title.
void Preview::frame(bool render) {
    fitSwapchain();
    uint64_t pixelSamples = 0;
    double passSeconds = 0.0;
    const bool showsLayer = !m_layers.showsRgb();
    if (showsLayer && (render || m_layerStale)) {
        // An AOV is pictured on the host from the sums (preview/layer_cycle.h): this frame's
        // passes first, waited for, then the picture of all the samples so far uploaded.
        const auto start = Clock::now();
        if (render) m_context->submitAndWait([&](VkCommandBuffer c) { pixelSamples = recordPasses(c, true); });
        passSeconds = secondsSince(start);
        m_toneMapper->setPixels(layerPixels(m_renderer->readback(0.0), m_layers.name()));
        m_layerStale = false;
    }
    std::optional<uint32_t> image = m_swapchain->acquire(m_frame->acquired);
    if (!image) m_recreateSwapchain = true;  // out of date: render anyway, show the next frame

    VkCommandBuffer cmd = m_frame->cmd;
    vkCheck(vkResetCommandBuffer(cmd, 0), "reset the preview's command buffer");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vkCheck(vkBeginCommandBuffer(cmd, &begin), "begin the preview's command buffer");

    if (showsLayer) {
        m_toneMapper->recordShowPixels(cmd);
    } else {
        pixelSamples = recordPasses(cmd, render);
        m_toneMapper->record(cmd, {m_exposure, m_settings.look.curve});
    }
    if (image) recordPresentation(cmd, m_swapchain->image(*image));
    vkCheck(vkEndCommandBuffer(cmd), "end the preview's command buffer");
    const double seconds = passSeconds + submitAndPresent(cmd, image);
    // Where the driver may cut loops short, the pixels they left short get the rest once
    // the passes are done (render/loop_budget.h); later frames and a save then see them.
    if (render && m_scheduler.finished()) m_renderer->renderSamplesCutLoopsLeft(m_scheduler.samplesDone());

    if (render && m_settings.rowsPerFrame == 0)
        m_rowBudget = adaptRowBudget(m_rowBudget, seconds, kTargetFrameSeconds, m_scene.film.height);
    m_titleSamples += pixelSamples;
    updateTitle(m_titleDirty || (m_scheduler.finished() && render));
}

// A swapchain of the window's framebuffer size (and a tone mapper for its format).
void Preview::fitSwapchain() {
    VkExtent2D framebuffer = m_window->framebufferSize();
    if (m_recreateSwapchain || m_swapchain->extent().width != framebuffer.width ||
        m_swapchain->extent().height != framebuffer.height) {
        m_swapchain->recreate(framebuffer);
        m_recreateSwapchain = false;
        if (m_swapchain->valid() && m_swapchain->isSrgb() != m_toneMapper->srgbImage()) {
            m_toneMapper.reset();
            m_toneMapper.emplace(*m_context, m_renderer->accumulation(), m_renderer->accumulationCompensation(),
                                 m_scene.film.width, m_scene.film.height, m_swapchain->isSrgb());
        }
    }
}

// This frame's passes (when `render`) into `cmd`; returns the pixel samples added.
uint64_t Preview::recordPasses(VkCommandBuffer cmd, bool render) {
    // The accumulation's clear (transfer) and earlier passes (shader writes, in earlier
    // submissions) -> this frame's passes and tone map.
    VkMemoryBarrier earlier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    earlier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    earlier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &earlier, 0, nullptr, 0, nullptr);
    uint64_t pixelSamples = 0;
    if (render) {
        // Each slice ends with a barrier: its accumulation writes -> the next slice's and the tone map's reads.
        for (const PassSlice& slice : m_scheduler.next(m_rowBudget)) {
            m_renderer->recordPasses(cmd, slice.firstSample, slice.count, slice.firstRow, slice.rowCount);
            pixelSamples += uint64_t(slice.count) * slice.rowCount * m_scene.film.width;
        }
    }
    return pixelSamples;
}

// The film letterboxed into swapchain image `target`, made ready to present.
void Preview::recordPresentation(VkCommandBuffer cmd, VkImage target) {
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    // The presentation engine's reads (done once the acquire semaphore, waited at the
    // transfer stage, is signalled) -> the clear's writes; old contents are discarded.
    VkImageMemoryBarrier toClear{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    toClear.srcAccessMask = 0;
    toClear.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    toClear.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    toClear.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    toClear.srcQueueFamilyIndex = toClear.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    toClear.image = target;
    toClear.subresourceRange = range;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr,
                         1, &toClear);
    VkClearColorValue grey{{0.1f, 0.1f, 0.1f, 1.0f}};
    vkCmdClearColorImage(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &grey, 1, &range);
    // The clear's writes (the letterbox) -> the blit's writes over the film's rectangle.
    VkImageMemoryBarrier toBlit = toClear;
    toBlit.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    toBlit.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    toBlit.oldLayout = toBlit.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr,
                         1, &toBlit);
    VkOffset2D offset;
    VkExtent2D size;
    fitFilm(m_scene.film.width, m_scene.film.height, m_swapchain->extent(), offset, size);
    m_toneMapper->recordBlit(cmd, target, offset, size);
    // The blit's writes -> presentation (made visible by the semaphore that present waits on).
    VkImageMemoryBarrier toPresent = toClear;
    toPresent.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    toPresent.dstAccessMask = 0;
    toPresent.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    toPresent.newLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &toPresent);
}

// Submits `cmd` and waits for it (waiting on the acquire and signalling the present
// semaphore when there is an image), then presents; returns the seconds from submission to completion.
double Preview::submitAndPresent(VkCommandBuffer cmd, std::optional<uint32_t> image) {
    VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    VkSemaphore rendered = image ? m_swapchain->renderedSemaphore(*image) : VK_NULL_HANDLE;
    if (image) {
        submit.waitSemaphoreCount = 1;
        submit.pWaitSemaphores = &m_frame->acquired;
        submit.pWaitDstStageMask = &waitStage;
        submit.signalSemaphoreCount = 1;
        submit.pSignalSemaphores = &rendered;
    }
    VkDevice device = m_context->device();
    vkCheck(vkResetFences(device, 1, &m_frame->fence), "reset the preview's frame fence");
    const auto start = Clock::now();
    vkCheck(vkQueueSubmit(m_context->queue(), 1, &submit, m_frame->fence), "submit a preview frame");
    vkCheck(vkWaitForFences(device, 1, &m_frame->fence, VK_TRUE, UINT64_MAX), "wait for a preview frame");
    const double seconds = secondsSince(start);
    if (image && !m_swapchain->present(*image)) m_recreateSwapchain = true;
    return seconds;
}

void Preview::save() {
    const std::string stem = m_scene.name.empty() ? std::string("preview") : m_scene.name;
    std::filesystem::path exr, png;
    for (int n = 1;; ++n) {
        std::string base = stem + "-preview-" + std::to_string(n);
        exr = base + ".exr";
        png = base + ".png";
        std::error_code ec;
        if (!std::filesystem::exists(exr, ec) && !std::filesystem::exists(png, ec)) break;
    }
    Image image = m_renderer->readback(secondsSince(m_restartTime));
    image.meta.spp = int(m_scheduler.samplesDone());  // rows ahead of that hold one sample more
    writeExr(exr, image);
    writePng(png, image, {m_exposure, m_settings.look.curve});
    std::fprintf(stderr, "preview: saved %s and %s (%u spp)\n", exr.string().c_str(), png.string().c_str(),
                 m_scheduler.samplesDone());
}

void Preview::updateTitle(bool force) {
    const double elapsed = secondsSince(m_titleTime);
    if (!force && elapsed < kTitleSeconds) return;
    m_titleDirty = false;
    if (elapsed >= kTitleSeconds || m_scheduler.finished()) {
        m_rate = elapsed > 0.0 ? double(m_titleSamples) / elapsed : 0.0;
        m_titleSamples = 0;
        m_titleTime = Clock::now();
    }
    char rate[64];
    if (m_scheduler.finished()) std::snprintf(rate, sizeof rate, "done");
    else std::snprintf(rate, sizeof rate, "%.2f M samples/s", m_rate * 1e-6);
    char text[512];
    std::snprintf(text, sizeof text, "%s | %s | %u/%u spp | %s | exposure %+.1f%s%s", m_scene.name.c_str(),
                  integratorLabel(m_integrator).c_str(), m_scheduler.samplesDone(), m_scheduler.spp(), rate,
                  double(m_exposure), m_layers.showsRgb() ? "" : " | layer ",
                  m_layers.showsRgb() ? "" : m_layers.name().c_str());
    m_window->setTitle(text);
}

}  // namespace

void runPreview(const Scene& scene, const PreviewSettings& settings) {
    Preview preview(scene, settings);
    preview.run();
}

}  // namespace penumbra::preview
#endif  // PENUMBRA_HAVE_GLFW
