// Renders a scene on the GPU by progressive accumulation: the scene is uploaded once,
// each pass adds one sample per pixel (for a band of rows) into a sum buffer, and the
// image is read back once at the end. The preview and batch modes drive the same object.
#pragma once

#include <algorithm>
#include <atomic>
#include <climits>
#include <functional>
#include <memory>
#include <optional>

#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/kernel.h"
#include "gpu/kernel_cache.h"
#include "image/image.h"
#include "render/kernel_options.h"
#include "render/node_reads.h"
#include "render/scene_arrays.h"
#include "scene/scene.h"

namespace penumbra {

struct RenderProgress {
    uint32_t samplesDone = 0;  // per pixel: samples every pixel has
    uint32_t samplesTotal = 0;
    double seconds = 0.0;          // since the render started
    double meanSamplesDone = 0.0;  // per pixel on average: past samplesDone while a sweep is part done

    // What the progress lines of `render` and `batch` show beside samplesDone / samplesTotal:
    // a sweep (render/pass_bands.h) gives every pixel many samples band by band, so the
    // share done, the rate and the time left follow the pixel samples handed out.
    double shareDone() const { return samplesTotal > 0 ? meanSamplesDone / samplesTotal : 0.0; }
    double samplesPerSecond(double pixels) const { return seconds > 0 ? meanSamplesDone * pixels / seconds : 0.0; }
    double secondsLeft() const {
        return meanSamplesDone > 0 ? seconds * (samplesTotal - meanSamplesDone) / meanSamplesDone : 0.0;
    }
};

// How Renderer::renderAll sizes its GPU submissions (render/pass_bands.h).
struct RenderPacing {
    double targetSeconds = 0.25;   // per submission: a stop waits about this long
    uint64_t maxPixelSamples = 0;  // per submission; 0: only the time bounds it (tests set it)
};

class Renderer {
public:
    // `kernels`, if given, supplies the integrator's pipeline, so that Renderers for several
    // scenes in one process (penumbra batch) compile each integrator once.
    // `bvhOptions` shape the scene's BVH (tests and benchmarks compare).
    Renderer(const gpu::Context& context, const Scene& scene, gpu::KernelCache* kernels = nullptr,
             const BvhOptions& bvhOptions = {});

    // Makes `scene` the next render while keeping everything uploaded: only RenderParams
    // (camera, sampler, integrator options) are re-uploaded, the kernel is switched if the
    // integrator type changed, and the accumulation is cleared. `scene` must flatten to the
    // same SceneArrays as the current scene: same geometry, materials, lights, film size and
    // light_selection (the caller knows, e.g. same file and overrides of camera/sampler/
    // integrator only). Throws std::logic_error when a checkable part of that differs.
    void retarget(const Scene& scene);

    // Clears the accumulation buffer (the next sample index restarts at 0) and the count of
    // loops cut short.
    void reset();
    // Re-upload the render parameters for a new camera / new integrator options (the
    // preview changes them live). Neither clears the accumulation: call reset() too.
    // Call only while no recorded pass is in flight. New options switch to a kernel
    // specialized for them (compiled on its first dispatch). setIntegrator keeps the
    // shader and the light-selection tables, so it throws std::invalid_argument when
    // `type` or `lightSelection` differ from the scene's.
    void setCamera(const Camera& camera);
    void setIntegrator(const IntegratorSettings& integrator);
    // How BRDF-sampled rays find emitters (render/emitter_first.h); EmitterFirst::Rule
    // unless set. Tests and benchmarks set Off or Exact to compare the two paths.
    void setEmitterFirst(EmitterFirst mode);
    // Whether small scenes' primitives go inline (render/inline_geometry.h); Rule unless set.
    void setInlineGeometry(InlineGeometry mode);
    // Where the traversal reads nodes from (render/node_reads.h); Device unless set.
    void setNodeReads(NodeReads mode);
    // Whether the kernels check for loops the driver cut short and take each pixel's samples
    // up from its own count (render/loop_budget.h); what loopsMayBeCutFor says for the device
    // unless set (tests turn the checks on where loops are whole, to compare).
    void setLoopChecks(bool on);
    // The worker threads the dispatches are shaped for (render/tile_queue.h: more than 1
    // makes each dispatch a tile queue, except with the loop checks on); what
    // workerThreadsFor says for the device unless set (tests compare several, min 1).
    void setWorkerThreads(uint32_t workers) { m_workerThreads = std::max<uint32_t>(workers, 1); }
    // How many invocations' traversal stacks the "_address" kernels' buffer holds, which
    // bounds their dispatches (render/traversal_stacks.h); stackInvocationsFor the film
    // unless set (tests set fewer, to split bands into several dispatches; never less than
    // a row of tiles).
    void setStackInvocations(uint32_t invocations);
    // Makes the driver compile the current kernel now, with a dispatch that covers no
    // pixels: llvmpipe compiles on the first dispatch, and callers that time the render
    // (penumbra:render_seconds) count that compilation as start-up, not as rendering.
    void compileKernel() const;
    // Records `count` passes, sample indices [first, first + count), over rows
    // [firstRow, firstRow + rowCount) into `cmd`, as one dispatch followed by a barrier; with
    // `firstColumn`, only columns [firstColumn, firstColumn + columnCount), where
    // firstColumn and columnCount are multiples of 8 or the run ends at the film's edge.
    // With the loop checks on (setLoopChecks), a pixel's samples start at its own count
    // instead of `first`, and a dispatch may leave some out: renderAll renders them.
    void recordPasses(VkCommandBuffer cmd, uint32_t first, uint32_t count, uint32_t firstRow, uint32_t rowCount,
                      uint32_t firstColumn = 0, uint32_t columnCount = UINT32_MAX) const;
    // Runs passes until the scene's spp is reached, calling `progress` after each
    // submission. Each submission is sized (render/pass_bands.h) to take about
    // `pacing.targetSeconds`, so a stop is seen promptly: if `cancel` becomes true the
    // render stops at the next submission, throwing std::runtime_error.
    void renderAll(const std::function<void(const RenderProgress&)>& progress = {},
                   const std::atomic<bool>* cancel = nullptr, const RenderPacing& pacing = RenderPacing());
    // On a driver that may cut loops short (render/loop_budget.h), after passes that should
    // have brought every pixel to `samples`: renders the samples that loops cut short since
    // the last reset() or renderAll left out, until none is cut (renderAll does this itself).
    // Throws gpu::GpuError where a single sample runs longer than the driver's loops may.
    void renderSamplesCutLoopsLeft(uint32_t samples, const std::atomic<bool>* cancel = nullptr);
    // Invocations whose loops the driver cut short since the last reset() or renderAll (each
    // left samples out, which renderSamplesCutLoopsLeft rendered); 0 where loops are whole.
    uint64_t loopCuts() const { return m_loopCuts; }
    // Rays traced (camera, shadow and BRDF rays) by `passes` passes over the whole film,
    // sample indices [0, passes), run with a ray-counting variant of the kernel; for
    // benchmarks (rays per second). The samples land in the accumulation: reset() after.
    uint64_t countRays(uint32_t passes);
    // Mean of the accumulated samples, with metadata (spp, seed, offset, integrator).
    Image readback(double renderSeconds) const;

    const Scene& scene() const { return m_scene; }
    // As buildSceneArrays made them, less the environment map's texels and table: those live
    // on the GPU alone (EnvironmentTexels::LeftOut; the table freed once uploaded).
    const SceneArrays& arrays() const { return m_arrays; }
    const gpu::Buffer& accumulation() const { return m_accum; }
    const gpu::Buffer& accumulationCompensation() const { return m_accumCompensation; }
    const gpu::RenderParams& params() const { return m_params; }

private:
    std::unique_ptr<gpu::Kernel> createKernel(const KernelOptions& options) const;
    // Switches to the kernel for the current integrator settings, unless it is already in use.
    void updateKernel();
    // The kernel options of the scene, the integrator settings and the set modes
    // (emitter first, inline geometry, node reads on this device).
    KernelOptions kernelOptions() const;
    // A dispatch's push constants: the samples and pixels it covers (as recordPasses says)
    // and, for the kernels that read nodes through their address, where the nodes and the
    // traversal stacks are.
    gpu::PassConstants passConstants(uint32_t first, uint32_t firstRow, uint32_t rowCount, uint32_t firstColumn,
                                     uint32_t count) const;
    // Records `kernel` for samples [first, first + count) over the pixels of rows
    // [firstRow, firstRow + rowCount) and columns [firstColumn, firstColumn + columnCount)
    // (checked by recordPasses), each dispatch followed by a barrier: one tile queue
    // (render/tile_queue.h) where there are several worker threads; else one dispatch, or,
    // for an "_address" kernel whose rows need more invocations than m_stacks holds, one
    // per run of tile rows that fits (render/traversal_stacks.h).
    void recordDispatches(VkCommandBuffer cmd, const gpu::Kernel& kernel, uint32_t first, uint32_t count,
                          uint32_t firstRow, uint32_t rowCount, uint32_t firstColumn, uint32_t columnCount) const;
    // The loops cut short since the counters were last cleared (kernel_common.glsl, main),
    // added to m_loopCuts; clears the counters.
    uint32_t takeLoopCuts();
    // Allocates m_stacks for m_stackInvocations when the current kernel reads nodes through
    // their address and it is not there yet.
    void allocateStacks();
    void uploadParams();

    const gpu::Context& m_context;
    gpu::KernelCache* m_kernels = nullptr;
    Scene m_scene;
    SceneArrays m_arrays;
    gpu::RenderParams m_params;
    EmitterFirst m_emitterFirst = EmitterFirst::Rule;
    InlineGeometry m_inlineGeometry = InlineGeometry::Rule;
    NodeReads m_nodeReads = NodeReads::Device;
    std::optional<bool> m_loopChecks;  // unset: as the device needs (loopsMayBeCutFor)
    uint64_t m_loopCuts = 0;
    KernelOptions m_options;
    uint32_t m_workerThreads = 1;     // render/tile_queue.h
    uint32_t m_stackDepth = 1;        // entries per traversal stack (childStackDepth)
    uint32_t m_stackInvocations = 0;  // invocations whose stacks m_stacks holds
    // Declaration order is teardown order in reverse: the kernel goes before the buffers.
    gpu::Buffer m_paramsBuffer, m_accum, m_accumCompensation, m_nodes, m_primitives, m_normals, m_materials, m_lights,
        m_lightTable, m_meshTable, m_counters;
    gpu::Buffer m_stacks;  // the "_address" kernels' traversal stacks (render/traversal_stacks.h), else empty
    gpu::Buffer m_materialTextures, m_textureTexels, m_uvs;  // textured scenes (render/texture_arrays.h)
    gpu::Buffer m_tangents;                                  // scenes with normal maps
    gpu::Buffer m_instances;                                 // scenes with instances (two-level BVH)
    gpu::Buffer m_environmentTexels, m_environmentTable;     // environment map (render/environment_map.h)
    gpu::Buffer m_lightBvh;                                  // light selection "bvh" (render/light_bvh_arrays.h)
    gpu::Buffer m_aovSums;  // film.aovs' sums (render/aov_layers.h), else a placeholder
    std::unique_ptr<gpu::Kernel> m_kernel;
};

// The layout of the render kernels' descriptor set (BINDING_* of shaders/shared/types.h).
std::vector<VkDescriptorType> renderBindings();

}  // namespace penumbra
