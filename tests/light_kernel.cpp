// Host side of the light-sampling test kernel (see light_kernel.h).
#include "light_kernel.h"

#include "gpu_fixture.h"

namespace penumbra::test {

static_assert(sizeof(gpu::LightTestPush) == 80 && sizeof(gpu::LightTestRecord) == 48);
// The test buffers must not take a scene buffer's binding.
static_assert(LIGHT_TEST_BINDING_IN >= BINDING_COUNT && LIGHT_TEST_BINDING_OUT >= BINDING_COUNT &&
              LIGHT_TEST_BINDING_IN != LIGHT_TEST_BINDING_OUT && LIGHT_TEST_BINDING_COUNT > LIGHT_TEST_BINDING_OUT);

namespace {

// Storage buffers, except the texel buffers of the traversal (geometry/bvh.glsl) and of the
// light data (lights/light_data.glsl).
std::vector<VkDescriptorType> lightTestBindings() {
    std::vector<VkDescriptorType> types(LIGHT_TEST_BINDING_COUNT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    for (uint32_t b : {uint32_t(BINDING_NODES), uint32_t(BINDING_PRIMITIVE_TEXELS), uint32_t(BINDING_LIGHTS),
                       uint32_t(BINDING_LIGHT_TABLE), uint32_t(BINDING_MESH_TABLE), uint32_t(BINDING_ENV_TEXELS),
                       uint32_t(BINDING_ENV_TABLE)})
        types[b] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    return types;
}

gpu::Kernel& lightTestKernel() {
    static gpu::Kernel kernel(gpuContext(), "tests/light_sampling", lightTestBindings(), sizeof(gpu::LightTestPush));
    return kernel;
}

}  // namespace

LightKernel::LightKernel(const SceneArrays& arrays)
    : m_ctx(gpuContext()),
      m_dummy(m_ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT),
      m_nodes(gpu::Buffer::fromVector(m_ctx, arrays.bvh.wideNodes,
                                      VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT)),
      m_primitives(gpu::Buffer::fromVector(
          m_ctx, arrays.bvh.primitives, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT)),
      m_normals(gpu::Buffer::fromVector(m_ctx, arrays.normals)),
      m_lights(gpu::Buffer::fromVector(m_ctx, arrays.lights, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT)),
      m_lightTable(gpu::Buffer::fromVector(m_ctx, arrays.lightTable, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT)),
      m_meshTable(gpu::Buffer::fromVector(m_ctx, arrays.meshTable, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT)),
      m_environmentTexels(
          gpu::Buffer::fromVector(m_ctx, arrays.environmentTexels, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT)),
      m_environmentTable(
          gpu::Buffer::fromVector(m_ctx, arrays.environmentTable, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT)),
      m_besideFirst(arrays.bvh.besideFirst()),
      m_besideCount(arrays.bvh.besideCount) {}

std::vector<gpu::LightTestRecord> LightKernel::run(gpu::LightTestPush push, const gpu::Buffer& in) {
    push.besideFirst = m_besideFirst;
    push.besideCount = m_besideCount;
    gpu::Buffer out(m_ctx, VkDeviceSize(push.count) * sizeof(gpu::LightTestRecord),
                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    // This scene's buffers at the render kernels' bindings (another LightKernel may have
    // bound its own since); bindings the kernel does not use still get a buffer.
    gpu::Kernel& kernel = lightTestKernel();
    for (uint32_t b : {uint32_t(BINDING_PARAMS), uint32_t(BINDING_ACCUM), uint32_t(BINDING_ACCUM_COMPENSATION),
                       uint32_t(BINDING_MATERIALS)})
        kernel.bind(b, m_dummy);
    kernel.bind(BINDING_NODES, m_nodes);
    kernel.bind(BINDING_NODE_WORDS, m_nodes);
    kernel.bind(BINDING_PRIMITIVES, m_primitives);
    kernel.bind(BINDING_PRIMITIVE_TEXELS, m_primitives);
    kernel.bind(BINDING_NORMALS, m_normals);
    kernel.bind(BINDING_LIGHTS, m_lights);
    kernel.bind(BINDING_LIGHT_TABLE, m_lightTable);
    kernel.bind(BINDING_MESH_TABLE, m_meshTable);
    kernel.bind(BINDING_ENV_TEXELS, m_environmentTexels);
    kernel.bind(BINDING_ENV_TABLE, m_environmentTable);
    kernel.bind(LIGHT_TEST_BINDING_IN, in);
    kernel.bind(LIGHT_TEST_BINDING_OUT, out);
    kernel.run((push.count + gpu::LIGHT_TEST_WORKGROUP_SIZE - 1) / gpu::LIGHT_TEST_WORKGROUP_SIZE, 1, 1, &push);
    auto records = out.read<gpu::LightTestRecord>();
    records.resize(push.count);
    return records;
}

gpu::LightTestPush LightKernel::shadingPointPush(uint32_t mode, uint32_t light, glm::vec3 x, glm::vec3 n,
                                                 uint32_t count, uint32_t sphereSampling, uint32_t quadSampling,
                                                 uint32_t triangleSampling) const {
    gpu::LightTestPush push{};
    push.mode = mode;
    push.x = x;
    push.n = n;
    push.light = light;
    push.count = count;
    push.sphereSampling = sphereSampling;
    push.quadSampling = quadSampling;
    push.triangleSampling = triangleSampling;
    push.minSolidAngle = m_minSolidAngle;
    push.minElevationSine = m_minElevationSine;
    return push;
}

std::vector<gpu::LightTestRecord> LightKernel::sample(uint32_t light, glm::vec3 x, glm::vec3 n, uint32_t sphereSampling,
                                                      uint32_t seed, uint32_t count, uint32_t quadSampling,
                                                      uint32_t triangleSampling) {
    gpu::LightTestPush push = shadingPointPush(gpu::LIGHT_TEST_MODE_SAMPLE, light, x, n, count, sphereSampling,
                                               quadSampling, triangleSampling);
    push.seed = seed;
    return run(push, m_dummy);
}

std::vector<double> LightKernel::pdf(uint32_t light, glm::vec3 x, glm::vec3 n, uint32_t sphereSampling,
                                     const std::vector<glm::vec3>& directions, std::vector<float>* hitDistance,
                                     uint32_t quadSampling, uint32_t triangleSampling) {
    std::vector<glm::vec4> dirs(directions.size());
    for (size_t i = 0; i < dirs.size(); ++i) dirs[i] = glm::vec4(directions[i], 0.0f);
    auto in = gpu::Buffer::fromVector(m_ctx, dirs);
    auto records = run(shadingPointPush(gpu::LIGHT_TEST_MODE_PDF, light, x, n, uint32_t(directions.size()),
                                        sphereSampling, quadSampling, triangleSampling),
                       in);
    std::vector<double> out(records.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = records[i].pdf;
    if (hitDistance) {
        hitDistance->resize(records.size());
        for (size_t i = 0; i < records.size(); ++i) (*hitDistance)[i] = records[i].tracedT;
    }
    return out;
}

std::vector<gpu::LightTestRecord> LightKernel::select(uint32_t table, uint32_t offset, uint32_t tableCount,
                                                      uint32_t seed, uint32_t count) {
    gpu::LightTestPush push{};
    push.mode = gpu::LIGHT_TEST_MODE_SELECT;
    push.table = table;
    push.tableOffset = offset;
    push.tableCount = tableCount;
    push.seed = seed;
    push.count = count;
    return run(push, m_dummy);
}

}  // namespace penumbra::test
