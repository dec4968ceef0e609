// Scene upload, pass recording and readback (see renderer.h).
#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "gpu/gpu_timer.h"
#include "gpu/vk_check.h"
#include "render/aov_layers.h"
#include "render/environment_map.h"
#include "render/loop_budget.h"
#include "render/pass_bands.h"
#include "render/tile_queue.h"
#include "render/traversal_stacks.h"
#include "scene/integrator_json.h"
#include "scene/integrator_options.h"
#include "shared/aov.h"

namespace penumbra {
namespace {

constexpr uint32_t kTile = PassBands::kTile;  // local_size_x/y of the integrator kernels
static_assert(kTile == TILE_SIZE);
// BINDING_COUNTERS: the rays traced, the tile queue's next pixel, the loops cut short.
constexpr uint32_t kCounterCount = 3;
constexpr VkDeviceSize kQueueCounterOffset = sizeof(uint32_t);
constexpr size_t kLoopsCutCounter = 2;

// Tiles across `pixels` (the last one partly outside).
uint32_t tilesFor(uint32_t pixels) { return (pixels + kTile - 1) / kTile; }

// The integrator's kernel: with `inlineCount` inline slots in use, its "_inline<N>" variant
// (render/inline_geometry.h, cmake/EmbedShaders.cmake), else the one for `nodeReads`
// (render/node_reads.h). An inline kernel reads NODE_READS_STORAGE_32 as NODE_READS_STORAGE.
std::string kernelName(IntegratorType type, uint32_t inlineCount, uint32_t nodeReads) {
    std::string name = type == IntegratorType::AmbientOcclusion ? "integrators/ao" : "integrators/direct";
    if (inlineCount == 0) return nodeReadsKernel(name, nodeReads);
    return name + "_inline" + std::to_string(inlineKernelCapacity(inlineCount));
}

}  // namespace

std::vector<VkDescriptorType> renderBindings() {
    std::vector<VkDescriptorType> types(BINDING_COUNT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    types[BINDING_PARAMS] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    types[BINDING_NODES] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_PRIMITIVE_TEXELS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_MATERIALS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_LIGHTS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_LIGHT_TABLE] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_MESH_TABLE] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_MATERIAL_TEXTURES] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_TEXTURE_TEXELS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_ENV_TEXELS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_ENV_TABLE] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    types[BINDING_LIGHT_BVH] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    return types;
}

Renderer::Renderer(const gpu::Context& context, const Scene& scene, gpu::KernelCache* kernels,
                   const BvhOptions& bvhOptions)
    : m_context(context),
      m_kernels(kernels),
      m_scene(scene),
      m_arrays(buildSceneArrays(scene, bvhOptions, EnvironmentTexels::LeftOut)),
      m_params(makeRenderParams(scene, m_arrays)),
      m_options(kernelOptions()),
      m_workerThreads(
          workerThreadsFor(context.info(), std::getenv("LP_NUM_THREADS"), std::thread::hardware_concurrency())),
      m_stackDepth(childStackDepth(m_arrays.bvh.wideNodes)),
      m_stackInvocations(stackInvocationsFor(tilesFor(m_params.width), tilesFor(m_params.height),
                                             stackInvocationLimit(gpu::BVH_STACKS_PER_INVOCATION * m_stackDepth))) {
    using gpu::Buffer;
    m_paramsBuffer = Buffer(context, sizeof(gpu::RenderParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, 0,
                            VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "render parameters");
    uploadParams();
    m_accum = Buffer(context, VkDeviceSize(m_params.width) * m_params.height * sizeof(gpu::AccumSum),
                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "accumulation");
    m_accumCompensation =
        Buffer(context, VkDeviceSize(m_params.width) * m_params.height * sizeof(gpu::AccumCompensation),
               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "accumulation compensation");
    // Nodes, primitives, materials, lights and alias tables are read as texel buffers
    // (bvh.glsl, materials.glsl, light_data.glsl); the nodes also as a storage buffer or
    // through their device address, where the device reads them so (render/node_reads.h),
    // and the primitives by the traversal tests' kernels.
    const VkBufferUsageFlags texels = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
    const VkBufferUsageFlags address = gpu::deviceAddressUsage(context);
    m_nodes = Buffer::fromVector(context, m_arrays.bvh.wideNodes, "BVH nodes",
                                 texels | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | address);
    // The groups' primitives follow the scene's (render/instance_arrays.h).
    if (m_arrays.instanced.primitives.empty())
        m_primitives = Buffer::fromVector(context, m_arrays.bvh.primitives, "primitives",
                                          texels | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    else
        m_primitives = Buffer::fromVector(context, allPrimitives(m_arrays.bvh, m_arrays.instanced), "primitives",
                                          texels | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    m_instances = Buffer::fromVector(context, m_arrays.instanced.instances, "instances");
    m_normals = Buffer::fromVector(context, m_arrays.normals, "triangle normals");
    m_materials = Buffer::fromVector(context, m_arrays.materials, "materials", texels);
    m_lights = Buffer::fromVector(context, m_arrays.lights, "lights", texels);
    m_lightTable = Buffer::fromVector(context, m_arrays.lightTable, "light selection table", texels);
    m_meshTable = Buffer::fromVector(context, m_arrays.meshTable, "mesh light table", texels);
    // Light selection "bvh" only; a placeholder otherwise, which the kernel never reads (kLightBvh).
    m_lightBvh = Buffer::fromVector(context, m_arrays.lightBvh.texels, "light BVH", texels);
    // The rays traced, the tile queue's next pixel and the loops cut short (BINDING_COUNTERS),
    // set by fills.
    m_counters = Buffer(context, kCounterCount * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 0,
                        VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "counters");
    // Untextured scenes get 16-byte placeholders: the kernel never reads them (hasTextures()).
    const TextureArrays& textures = m_arrays.textures;
    m_materialTextures = Buffer::fromVector(context, textures.materialTextures, "material textures", texels);
    m_textureTexels = Buffer::fromVector(context, textures.texels, "texture texels", texels);
    m_uvs = Buffer::fromVector(context, textures.uvs, "texture coordinates");
    m_tangents = Buffer::fromVector(context, textures.tangents, "tangents");  // normal maps only
    // Scenes without an environment map get placeholders too (hasEnvironmentMap()).
    // 512 MiB each for an 8192 x 4096 map: the table's host copy goes once uploaded, and the
    // texels are written from the scene's map straight into GPU memory (on lavapipe device
    // memory is host memory), so that at most one host copy of either exists at a time.
    m_environmentTable = Buffer::fromVector(context, m_arrays.environmentTable, "environment map table", texels);
    std::vector<gpu::AliasEntry>().swap(m_arrays.environmentTable);
    const EnvironmentImage* map = nullptr;
    for (const Light& l : m_scene.lights)
        if (l.map) map = l.map.get();  // the loaders allow one map, alone (appendLightsWithoutGeometry)
    const size_t mapTexels = map ? map->texels.size() : 0;
    m_environmentTexels = Buffer(context, mapTexels * sizeof(glm::vec4), texels, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                                 "environment map texels");
    if (map)
        m_environmentTexels.write(mapTexels * sizeof(glm::vec4),
                                  [&](void* out) { writeEnvironmentTexels(*map, static_cast<glm::vec4*>(out)); });

    // The AOV sums (shared/aov.h); a placeholder for scenes without AOVs, whose kernels
    // never touch it (kAovs == 0).
    const VkDeviceSize aovBytes = m_options.aovs != 0 ? VkDeviceSize(m_params.width) * m_params.height *
                                                            gpu::AOV_VEC4S * sizeof(glm::vec4)
                                                      : sizeof(glm::vec4);
    m_aovSums = Buffer(context, aovBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                       "AOV sums");

    allocateStacks();
    m_kernel = createKernel(m_options);
    reset();
}

void Renderer::allocateStacks() {
    if (m_options.nodeReads != NODE_READS_ADDRESS || m_stacks.handle() != VK_NULL_HANDLE) return;
    m_stacks = gpu::Buffer(
        m_context, VkDeviceSize(m_stackInvocations) * gpu::BVH_STACKS_PER_INVOCATION * m_stackDepth * sizeof(uint32_t),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | gpu::deviceAddressUsage(m_context), 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
        "traversal stacks");
}

void Renderer::setStackInvocations(uint32_t invocations) {
    m_stackInvocations = stackInvocationsFor(tilesFor(m_params.width), 1, invocations);
    m_stacks = gpu::Buffer();
    allocateStacks();
}

std::unique_ptr<gpu::Kernel> Renderer::createKernel(const KernelOptions& options) const {
    const std::string name = kernelName(m_scene.integrator.type, options.inlineGeometry.slotCount(), options.nodeReads);
    const uint32_t pushBytes = uint32_t(sizeof(gpu::PassConstants));
    auto spec = options.specialization();
    auto kernel = m_kernels ? m_kernels->kernel(name, renderBindings(), pushBytes, spec)
                            : std::make_unique<gpu::Kernel>(m_context, name, renderBindings(), pushBytes, spec);
    kernel->bind(BINDING_PARAMS, m_paramsBuffer);
    kernel->bind(BINDING_ACCUM, m_accum);
    kernel->bind(BINDING_ACCUM_COMPENSATION, m_accumCompensation);
    kernel->bind(BINDING_NODES, m_nodes);
    kernel->bind(BINDING_NODE_WORDS, m_nodes);
    kernel->bind(BINDING_PRIMITIVES, m_primitives);
    kernel->bind(BINDING_PRIMITIVE_TEXELS, m_primitives);
    kernel->bind(BINDING_NORMALS, m_normals);
    kernel->bind(BINDING_MATERIALS, m_materials);
    kernel->bind(BINDING_LIGHTS, m_lights);
    kernel->bind(BINDING_LIGHT_TABLE, m_lightTable);
    kernel->bind(BINDING_MESH_TABLE, m_meshTable);
    kernel->bind(BINDING_COUNTERS, m_counters);
    kernel->bind(BINDING_MATERIAL_TEXTURES, m_materialTextures);
    kernel->bind(BINDING_TEXTURE_TEXELS, m_textureTexels);
    kernel->bind(BINDING_UVS, m_uvs);
    kernel->bind(BINDING_TANGENTS, m_tangents);
    kernel->bind(BINDING_INSTANCES, m_instances);
    kernel->bind(BINDING_ENV_TEXELS, m_environmentTexels);
    kernel->bind(BINDING_ENV_TABLE, m_environmentTable);
    kernel->bind(BINDING_AOV, m_aovSums);
    kernel->bind(BINDING_LIGHT_BVH, m_lightBvh);
    return kernel;
}

void Renderer::setEmitterFirst(EmitterFirst mode) {
    m_emitterFirst = mode;
    updateKernel();
}

void Renderer::setNodeReads(NodeReads mode) {
    m_nodeReads = mode;
    updateKernel();
}

void Renderer::setLoopChecks(bool on) {
    m_loopChecks = on;
    updateKernel();
}

void Renderer::setInlineGeometry(InlineGeometry mode) {
    m_inlineGeometry = mode;
    updateKernel();
}

KernelOptions Renderer::kernelOptions() const {
    KernelOptions options = makeKernelOptions(m_scene, m_arrays, m_emitterFirst, m_inlineGeometry);
    options.nodeReads = nodeReadsValue(m_nodeReads, m_context.info());
    if (!m_arrays.instanced.instances.empty()) options.nodeReads = nodeReadsWithInstances(options.nodeReads);
    options.loopsMayBeCut = m_loopChecks.value_or(loopsMayBeCutFor(m_context.info())) ? 1 : 0;
    return options;
}

void Renderer::updateKernel() {
    const KernelOptions options = kernelOptions();
    if (m_kernel && options == m_options) return;
    m_options = options;
    allocateStacks();
    m_kernel = createKernel(m_options);
}

void Renderer::retarget(const Scene& scene) {
    const Scene& old = m_scene;
    if (scene.film.width != old.film.width || scene.film.height != old.film.height ||
        scene.film.aovs != old.film.aovs || needsNewUpload(scene.integrator, old.integrator) ||
        scene.shapes.size() != old.shapes.size() || scene.materials.size() != old.materials.size() ||
        scene.lights.size() != old.lights.size())
        throw std::logic_error("Renderer::retarget: " + scene.path + " does not share the uploaded scene of " +
                               old.path);
    const bool sameType = scene.integrator.type == old.integrator.type;
    m_scene = scene;
    uploadParams();
    if (!sameType) m_kernel.reset();  // a new shader, even with equal options
    updateKernel();
    reset();
}

void Renderer::reset() {
    m_accum.clear();
    m_accumCompensation.clear();
    if (m_options.aovs != 0) m_aovSums.clear();
    // And the loops cut short so far (renderSamplesCutLoopsLeft), which only kernels with the
    // checks count.
    if (m_options.loopsMayBeCut) m_counters.clear();
    m_loopCuts = 0;
}

void Renderer::setCamera(const Camera& camera) {
    m_scene.camera = camera;
    uploadParams();
}

void Renderer::setIntegrator(const IntegratorSettings& integrator) {
    if (integrator.type != m_scene.integrator.type)
        throw std::invalid_argument("the integrator type cannot change without a new kernel");
    if (needsNewUpload(integrator, m_scene.integrator))
        throw std::invalid_argument("light selection cannot change without rebuilding the light tables");
    m_scene.integrator = integrator;
    uploadParams();
    updateKernel();
}

void Renderer::uploadParams() {
    m_params = makeRenderParams(m_scene, m_arrays);
    m_paramsBuffer.upload(&m_params, sizeof(m_params));
}

gpu::PassConstants Renderer::passConstants(uint32_t first, uint32_t firstRow, uint32_t rowCount, uint32_t firstColumn,
                                           uint32_t count) const {
    const VkDeviceAddress nodes = m_nodes.address(), stacks = m_stacks.address();
    return {first,
            firstRow,
            rowCount,
            firstColumn,
            count,
            uint32_t(nodes),
            uint32_t(nodes >> 32),
            uint32_t(stacks),
            uint32_t(stacks >> 32),
            m_stackDepth,
            0,
            0,
            LOOP_PROBE_TRIPS};
}

void Renderer::compileKernel() const {
    const gpu::PassConstants pass = passConstants(0, 0, 0, 0, 1);  // rowCount 0: every invocation returns at once
    m_kernel->run(1, 1, 1, &pass);
}

void Renderer::recordPasses(VkCommandBuffer cmd, uint32_t first, uint32_t count, uint32_t firstRow, uint32_t rowCount,
                            uint32_t firstColumn, uint32_t columnCount) const {
    if (count == 0) return;
    rowCount = std::min(rowCount, m_params.height - std::min(firstRow, m_params.height));
    columnCount = std::min(columnCount, m_params.width - std::min(firstColumn, m_params.width));
    if (rowCount == 0 || columnCount == 0) return;
    // The kernel bounds rows by rowCount but columns only by the film's width: a run of
    // columns is whole tiles, or ends at the edge.
    if (firstColumn % kTile != 0 || (columnCount % kTile != 0 && firstColumn + columnCount != m_params.width))
        throw std::logic_error("recordPasses: a run of columns must be whole tiles or end at the film's edge");
    recordDispatches(cmd, *m_kernel, first, count, firstRow, rowCount, firstColumn, columnCount);
}

void Renderer::recordDispatches(VkCommandBuffer cmd, const gpu::Kernel& kernel, uint32_t first, uint32_t count,
                                uint32_t firstRow, uint32_t rowCount, uint32_t firstColumn,
                                uint32_t columnCount) const {
    const uint32_t tileColumns = tilesFor(columnCount), tileRows = tilesFor(rowCount);
    // allocateStacks made them for every kernel that reads nodes by address.
    const bool stacks = m_options.nodeReads == NODE_READS_ADDRESS;
    // Not where the driver may cut loops short (render/loop_budget.h): the queue's few
    // workgroups would have the loop budget of a few SIMD groups for a whole band.
    if (usesTileQueue(m_workerThreads) && !m_options.loopsMayBeCut) {
        gpu::PassConstants pass = passConstants(first, firstRow, rowCount, firstColumn, count);
        pass.queueTiles = tileColumns * tileRows;
        pass.tileColumns = tileColumns;
        const uint32_t groups = tileQueueWorkgroups(pass.queueTiles, m_workerThreads,
                                                    stacks ? m_stackInvocations / TILE_PIXELS : UINT32_MAX);
        if (stacks && invocationsOf(groups) > m_stackInvocations)
            throw std::logic_error("recordDispatches: a tile queue has more invocations than the traversal stacks");
        // The queue starts at the band's first pixel; the previous dispatch's atomics are done.
        gpu::fillBetweenDispatches(cmd, m_counters, kQueueCounterOffset, sizeof(uint32_t), 0);
        kernel.record(cmd, groups, 1, 1, &pass);
        gpu::computeToComputeBarrier(cmd);
        return;
    }
    const uint32_t step = stacks ? tileRowsPerDispatch(tileColumns, m_stackInvocations) : tileRows;
    for (uint32_t row = 0; row < tileRows; row += step) {
        const uint32_t rows = std::min(step, tileRows - row);
        if (stacks && invocationsOf(uint64_t(tileColumns) * rows) > m_stackInvocations)
            throw std::logic_error("recordDispatches: a dispatch has more invocations than the traversal stacks");
        // One dispatch adds all `count` samples (integrators/kernel_common.glsl, main).
        const gpu::PassConstants pass = passConstants(
            first, firstRow + row * kTile, std::min(rows * kTile, rowCount - row * kTile), firstColumn, count);
        kernel.record(cmd, tileColumns, rows, 1, &pass);
        // These sums -> the next band / readback; these stacks -> the next dispatch's.
        gpu::computeToComputeBarrier(cmd);
    }
}

void Renderer::renderAll(const std::function<void(const RenderProgress&)>& progress, const std::atomic<bool>* cancel,
                         const RenderPacing& pacing) {
    using Clock = std::chrono::steady_clock;
    const uint32_t total = m_scene.sampler.spp;
    const auto start = Clock::now();
    // The loops cut short in this render, counted from here (renderSamplesCutLoopsLeft).
    m_loopCuts = 0;
    if (m_options.loopsMayBeCut) m_counters.clear();
    // Each submission is sized to take about pacing.targetSeconds (render/pass_bands.h), by
    // the device's time for it: the wall time also holds a fixed cost per submission that
    // does not grow with the work (gpu/gpu_timer.h).
    // The first band, before anything is measured, is sized from the rays a pixel sample
    // may trace (the bound countRays uses) at a throughput below any measured on lavapipe
    // (0.2 Mrays/s, the 1M-triangle scene under heavy load): ordinary settings start with
    // thousands of pixels instead of one tile, which saves lavapipe's fixed cost of ~20
    // submissions on small renders, while heavy ones (thousands of samples per pixel)
    // still start with a single tile.
    constexpr double kSlowestRaysPerSecond = 2e5;
    const double raysPerPixelSample = 1.0 + 2.0 * double(m_options.lightAndBsdfSamples());
    const auto firstBandPixels = uint64_t(pacing.targetSeconds * kSlowestRaysPerSecond / raysPerPixelSample);
    const gpu::GpuTimer timer(m_context, PassBands::kMaxBandsPerSubmission);
    // Several bands per submission only where each can be timed (pass_bands.h).
    PassBands bands(m_params.width, m_params.height, total, pacing.maxPixelSamples, firstBandPixels,
                    timer.supported() ? PassBands::kMaxBandsPerSubmission : 1);
    while (!bands.finished()) {
        if (cancel && cancel->load()) throw std::runtime_error("render interrupted");
        const std::vector<PassBand> plan = bands.next(pacing.targetSeconds);
        const auto t0 = Clock::now();
        m_context.submitAndWait([&](VkCommandBuffer cmd) {
            timer.start(cmd, uint32_t(plan.size()));
            for (size_t i = 0; i < plan.size(); ++i) {
                const PassBand& b = plan[i];
                recordPasses(cmd, b.firstSample, b.count, b.firstRow, b.rowCount, b.firstColumn, b.columnCount);
                timer.stop(cmd, uint32_t(i));
            }
        });
        std::vector<double> device = timer.seconds(uint32_t(plan.size()));
        // Without timestamps, the wall time for each band: an overestimate, never an under-.
        if (std::any_of(device.begin(), device.end(), [](double t) { return t < 0.0; }))
            device.assign(plan.size(), std::chrono::duration<double>(Clock::now() - t0).count());
        bands.measured(device);
        if (progress)
            progress({.samplesDone = bands.samplesDone(),
                      .samplesTotal = total,
                      .seconds = std::chrono::duration<double>(Clock::now() - start).count(),
                      .meanSamplesDone = bands.meanSamplesDone()});
    }
    renderSamplesCutLoopsLeft(total, cancel);
}

uint32_t Renderer::takeLoopCuts() {
    const uint32_t cuts = m_counters.read<uint32_t>()[kLoopsCutCounter];
    m_counters.clear();
    m_loopCuts += cuts;
    return cuts;
}

void Renderer::renderSamplesCutLoopsLeft(uint32_t samples, const std::atomic<bool>* cancel) {
    // The kernels counted the invocations whose loops were cut (kernel_common.glsl, main)
    // since the counters were cleared. Each left its pixel short; passes over the whole film
    // up to `samples` give every pixel the rest, from its own count, until every pixel has
    // them all. Each pass renders at least one sample more, unless a single sample runs
    // longer than the driver's loops may.
    if (!m_options.loopsMayBeCut) return;
    auto samplesDone = [&] {
        double sum = 0.0;
        for (const gpu::AccumSum& s : m_accum.read<gpu::AccumSum>()) sum += s.count;
        return sum;
    };
    const double all = double(m_params.width) * m_params.height * samples;
    double done = samplesDone();
    while (takeLoopCuts() > 0 && done < all) {
        if (cancel && cancel->load()) throw std::runtime_error("render interrupted");
        m_context.submitAndWait(
            [&](VkCommandBuffer cmd) { recordPasses(cmd, 0, samples, 0, m_params.height, 0, m_params.width); });
        const double now = samplesDone();
        if (!(now > done))
            throw gpu::GpuError("this Vulkan driver (" + m_context.info().driverInfo +
                                ") ends a shader's loops after 65535 iterations, before one sample of this scene "
                                "is traced; use Mesa 25 or later (tools/setup installs it) or a GPU");
        done = now;
    }
}

uint64_t Renderer::countRays(uint32_t passes) {
    KernelOptions counting = m_options;
    counting.countRays = 1;
    auto kernel = createKernel(counting);
    // One pass per submission, counted in 32 bits: at most a camera ray plus, per light or
    // BRDF sample, a traced ray and a shadow ray for a delta light.
    const uint64_t raysPerPixel = 1 + 2 * uint64_t(m_options.lightAndBsdfSamples());
    if (uint64_t(m_params.width) * m_params.height * raysPerPixel > UINT32_MAX)
        throw std::runtime_error("countRays: a pass may trace more than 2^32 rays; use a smaller film");
    uint64_t total = 0;
    for (uint32_t i = 0; i < passes; ++i) {
        m_counters.clear();
        m_context.submitAndWait(
            [&](VkCommandBuffer cmd) { recordDispatches(cmd, *kernel, i, 1, 0, m_params.height, 0, m_params.width); });
        total += m_counters.read<uint32_t>()[0];  // the rays traced
    }
    return total;
}

Image Renderer::readback(double renderSeconds) const {
    auto sums = m_accum.read<gpu::AccumSum>();
    auto compensations = m_accumCompensation.read<gpu::AccumCompensation>();
    Image image;
    image.width = m_params.width;
    image.height = m_params.height;
    image.rgb.resize(size_t(image.width) * image.height * 3);
    for (size_t i = 0; i < size_t(image.width) * image.height; ++i) {
        const gpu::AccumSum& s = sums[i];
        const glm::vec3 compensation = compensations[i].compensation;
        // The compensated sum (shared/types.h, AccumSum) times 1/count rounded once to
        // float: where the compensation is 0 and the count below 2^24, the same operations
        // and bits as a plain float sum and count gave.
        const float inv = s.count > 0 ? float(1.0 / double(s.count)) : 0.0f;
        for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] = float(double(s.sum[c]) - double(compensation[c])) * inv;
    }
    image.meta.spp = int(m_scene.sampler.spp);
    image.meta.seed = int(m_scene.sampler.seed);
    image.meta.sampleOffset = int(m_scene.sampler.sampleOffset);
    image.meta.integrator = integratorJson(m_scene.integrator).dump();
    image.meta.renderSeconds = renderSeconds;
    image.meta.sampler = toName(m_scene.sampler.type);
    if (m_options.aovs != 0)
        image.aovs = aovLayers(m_scene.film.aovs, m_aovSums.read<glm::vec4>(), image, m_scene, m_arrays.bvh);
    return image;
}

}  // namespace penumbra
