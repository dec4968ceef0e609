// penumbra_microbench: how fast a compute kernel on this Vulkan device fetches BVH-like
// nodes inside a divergent loop, from each kind of memory a kernel can read (storage,
// uniform and texel buffers, workgroup memory, buffer device addresses, packed nodes), and
// what the traversal stack costs (local array, workgroup memory, short stack, restart
// trail), and what a traversal step costs with rays or a node's children across the SIMD
// lanes. Kernels: tools/bench/microbenchmarks/shaders; run everything with tools/bench/microbench.
#include <algorithm>
#include <bit>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <vulkan/vulkan.h>

#include "bench_harness.h"
#include "bvh/bvh.h"
#include "bvh/intersect.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/vk_check.h"
#include "hash.h"

namespace {

using penumbra::bench::BenchBinding;
using penumbra::bench::BenchKernel;
using penumbra::bench::kWorkgroup;
using penumbra::bench::loadAverage;
using penumbra::bench::median;
using penumbra::bench::readSpirv;
using penumbra::gpu::Context;
using penumbra::gpu::vkCheck;
namespace gpu = penumbra::gpu;
using penumbra::decodeWideChild;
using penumbra::intersectBox;
using penumbra::WideChildBox;

constexpr uint32_t kSmallNodes = 1024;  // SMALL_NODES in fetch.comp: 32 KiB of 32-byte nodes
constexpr uint32_t kLargeNodes = 1u << 20;

struct Push {
    uint32_t address[2];
    uint32_t mask;
    uint32_t threshold;
    float boxOrigin[4];
    float boxScale[4];
};

// A host-visible buffer (on lavapipe all memory is), optionally with a texel view and a
// device address.
class HostBuffer {
public:
    HostBuffer(const Context& context, const void* data, VkDeviceSize size, VkBufferUsageFlags usage,
               VkFormat viewFormat = VK_FORMAT_UNDEFINED)
        : m_device(context.device()), m_size(size) {
        VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        info.size = size;
        info.usage = usage;
        info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
        vkCheck(vkCreateBuffer(m_device, &info, nullptr, &m_buffer), "create buffer");
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(m_device, m_buffer, &req);
        VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
        flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        if (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) alloc.pNext = &flags;
        alloc.allocationSize = req.size;
        alloc.memoryTypeIndex = context.findMemoryType(
            req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        vkCheck(vkAllocateMemory(m_device, &alloc, nullptr, &m_memory), "allocate buffer memory");
        vkCheck(vkBindBufferMemory(m_device, m_buffer, m_memory, 0), "bind buffer memory");
        vkCheck(vkMapMemory(m_device, m_memory, 0, size, 0, &m_mapped), "map buffer memory");
        if (data) std::memcpy(m_mapped, data, size_t(size));
        else std::memset(m_mapped, 0, size_t(size));
        if (viewFormat != VK_FORMAT_UNDEFINED) {
            VkBufferViewCreateInfo view{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
            view.buffer = m_buffer;
            view.format = viewFormat;
            view.range = VK_WHOLE_SIZE;
            vkCheck(vkCreateBufferView(m_device, &view, nullptr, &m_view), "create buffer view");
        }
        if (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT)
            m_address = penumbra::gpu::deviceAddressOf(m_device, m_buffer);
    }
    ~HostBuffer() {
        if (m_view) vkDestroyBufferView(m_device, m_view, nullptr);
        vkDestroyBuffer(m_device, m_buffer, nullptr);
        vkFreeMemory(m_device, m_memory, nullptr);
    }
    HostBuffer(const HostBuffer&) = delete;
    HostBuffer& operator=(const HostBuffer&) = delete;

    VkBuffer buffer() const { return m_buffer; }
    VkBufferView view() const { return m_view; }
    VkDeviceAddress address() const { return m_address; }
    const void* data() const { return m_mapped; }
    VkDeviceSize size() const { return m_size; }

private:
    VkDevice m_device;
    VkDeviceSize m_size;
    VkBuffer m_buffer = VK_NULL_HANDLE;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
    VkBufferView m_view = VK_NULL_HANDLE;
    VkDeviceAddress m_address = 0;
    void* m_mapped = nullptr;
};

// One kernel variant reading `nodes` at binding 1 (when it reads them through a
// descriptor) and writing `results` at binding 0; STEPS (constant_id 0) = `steps`.
std::unique_ptr<BenchKernel> makeBench(const Context& context, const std::string& spirv, uint32_t steps,
                                       VkDescriptorType nodeType, const HostBuffer& nodes, const HostBuffer& results,
                                       const Push& push, uint32_t invocations) {
    BenchBinding resultBinding;
    resultBinding.binding = 0;
    resultBinding.buffer = results.buffer();
    BenchBinding nodeBinding;
    nodeBinding.binding = 1;
    nodeBinding.type = nodeType;
    nodeBinding.buffer = nodes.buffer();
    nodeBinding.texelView = nodes.view();
    return std::make_unique<BenchKernel>(
        context, readSpirv(spirv, "penumbra_microbench"), std::vector<BenchBinding>{resultBinding, nodeBinding}, &push,
        uint32_t(sizeof(Push)), invocations / kWorkgroup, std::vector<uint32_t>{steps});
}

// The node tables of one size, in every layout the kernels read.
struct Tables {
    std::vector<float> nodes32;     // per node: min.xyz, next; max.xyz, 0
    std::vector<uint32_t> nodes16;  // per node: next, unorm8 (min.xyz, max.x), unorm8 (max.yz), 0
    std::vector<uint32_t> nodes8;   // per node: next, six 5-bit planes
};

// Boxes in [0, 1.5)^3, quantized against the origin 0 and scale 1.5 (the packed kernels'
// push constants). `next` is uniform over the table, so walks scatter over all of it.
Tables makeTables(uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    Tables t;
    t.nodes32.resize(size_t(count) * 8);
    t.nodes16.resize(size_t(count) * 4);
    t.nodes8.resize(size_t(count) * 2);
    auto q8 = [](float v) { return uint32_t(std::lround(std::clamp(v / 1.5f, 0.0f, 1.0f) * 255.0f)); };
    auto q5 = [](float v) { return uint32_t(std::lround(std::clamp(v / 1.5f, 0.0f, 1.0f) * 31.0f)); };
    for (uint32_t i = 0; i < count; ++i) {
        float lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
            lo[k] = unit(rng);
            hi[k] = lo[k] + 0.5f * unit(rng);
        }
        uint32_t next = uint32_t(rng()) % count;
        float* n = &t.nodes32[size_t(i) * 8];
        n[0] = lo[0], n[1] = lo[1], n[2] = lo[2], n[3] = float(next);
        n[4] = hi[0], n[5] = hi[1], n[6] = hi[2], n[7] = 0.0f;
        uint32_t* p = &t.nodes16[size_t(i) * 4];
        p[0] = next;
        p[1] = q8(lo[0]) | q8(lo[1]) << 8 | q8(lo[2]) << 16 | q8(hi[0]) << 24;
        p[2] = q8(hi[1]) | q8(hi[2]) << 8;
        p[3] = 0;
        uint32_t* e = &t.nodes8[size_t(i) * 2];
        e[0] = next;
        e[1] = q5(lo[0]) | q5(lo[1]) << 5 | q5(lo[2]) << 10 | q5(hi[0]) << 15 | q5(hi[1]) << 20 | q5(hi[2]) << 25;
    }
    return t;
}

// Node tables of step.comp: four-wide nodes as the renderer's (gpu::WideNode) and
// eight-wide nodes of 24 words (step.comp says how they are laid out). Every child exists
// and its box, origin 0 and step 2^-8 on each axis, lies in [0, 1)^3.
struct StepTables {
    uint32_t count4 = 0, count8 = 0;
    std::vector<gpu::WideNode> wide4;
    std::vector<uint32_t> wide4Float, wide8;  // wide4Float: wide4's boxes as floats
};

constexpr uint32_t kStepExponents = 119u | 119u << 8 | 119u << 16;  // 2^(119 - 127) = 2^-8
constexpr float kStep = 1.0f / 256.0f;
// The four-wide nodes' frame (shared/types.h): planes base + 2^(E - 127) + q * 2^(E - 142)
// with E = 134 and base = -2^7 are q * 2^-8 exactly, the eight-wide nodes' planes.
constexpr uint32_t kWideExponents = 134u | 134u << 8 | 134u << 16;
constexpr float kWideBase = -128.0f;

StepTables makeStepTables(uint32_t count4, uint32_t count8, uint32_t seed) {
    std::mt19937 rng(seed);
    StepTables t;
    t.count4 = count4;
    t.count8 = count8;
    auto planes = [&](uint32_t lo[3], uint32_t hi[3]) {
        for (int k = 0; k < 3; ++k) {
            lo[k] = rng() % 200;
            hi[k] = lo[k] + 1 + rng() % 55;
        }
    };
    t.wide4.assign(count4, gpu::WideNode{});
    for (gpu::WideNode& n : t.wide4) {
        n.meta = kWideExponents | gpu::WIDE_ALL_CHILDREN << gpu::WIDE_CHILD_MASK_SHIFT;
        n.base = glm::vec3(kWideBase);
        uint32_t* loPlanes[3] = {&n.loX, &n.loY, &n.loZ};
        uint32_t* hiPlanes[3] = {&n.hiX, &n.hiY, &n.hiZ};
        uint32_t* refs[4] = {&n.child0, &n.child1, &n.child2, &n.child3};
        for (uint32_t c = 0; c < 4; ++c) {
            uint32_t lo[3], hi[3];
            planes(lo, hi);
            for (int k = 0; k < 3; ++k) {
                *loPlanes[k] |= lo[k] << (8 * c);
                *hiPlanes[k] |= hi[k] << (8 * c);
            }
            *refs[c] = uint32_t(rng()) % count4;
        }
    }
    // The same nodes with each plane decoded as the traversal decodes it (decodeWideChild):
    // 32 words a node, the planes loX[4] loY[4] loZ[4] hiX[4] hiY[4] hiZ[4], the four
    // references, the meta word.
    t.wide4Float.assign(size_t(count4) * 32, 0);
    for (uint32_t i = 0; i < count4; ++i) {
        uint32_t* f = &t.wide4Float[size_t(i) * 32];
        for (uint32_t c = 0; c < 4; ++c) {
            const WideChildBox box = decodeWideChild(t.wide4[i], c);
            for (int k = 0; k < 3; ++k) {
                f[4 * k + c] = std::bit_cast<uint32_t>(box.lo[k]);
                f[4 * (3 + k) + c] = std::bit_cast<uint32_t>(box.hi[k]);
            }
            f[24 + c] = box.ref;
        }
        f[28] = t.wide4[i].meta;
    }
    t.wide8.assign(size_t(count8) * 24, 0);
    for (uint32_t i = 0; i < count8; ++i) {
        uint32_t* n = &t.wide8[size_t(i) * 24];
        n[3] = kStepExponents | 0xffu << gpu::WIDE_CHILD_MASK_SHIFT;
        n[4] = uint32_t(rng()) % count8;
        for (uint32_t c = 0; c < 8; ++c) {
            uint32_t lo[3], hi[3];
            planes(lo, hi);
            n[8 + 2 * c] = lo[0] | lo[1] << 8 | lo[2] << 16 | hi[0] << 24;
            n[9 + 2 * c] = hi[1] | hi[2] << 8 | (uint32_t(rng()) & 0xffffu) << 16;
        }
    }
    return t;
}

// step.comp's walk of ray `ray` replayed on the CPU with the traversal's own box decode and
// test (decodeWideChild, intersectBox: the same operations in the same order; the build
// does not contract them, and lavapipe does not fuse): its (acc, node).
std::pair<float, float> replayStep(const StepTables& t, bool children8, uint32_t ray, uint32_t steps) {
    const uint32_t salt = lowbias32(ray);
    glm::vec3 origin, invDir;
    for (uint32_t k = 0; k < 3; ++k) {
        origin[k] = float((salt >> (8 * k)) & 255u) * (1.0f / 256.0f);
        invDir[k] = (float(lowbias32(salt + k) & 1023u) - 511.5f) * (1.0f / 64.0f);
    }
    const uint32_t mask = (children8 ? t.count8 : t.count4) - 1, arity = children8 ? 8 : 4;
    uint32_t node = salt & mask;
    float acc = 0.0f;
    for (uint32_t s = 0; s < steps; ++s) {
        const uint32_t* n8 = &t.wide8[children8 ? size_t(node) * 24 : 0];
        uint32_t hits = 0, next = 0, fallback = 0;  // fallback: where the ray goes when no box is hit
        float best = 0.0f;
        for (uint32_t c = 0; c < arity; ++c) {
            WideChildBox box;
            if (children8) {
                const uint32_t a = n8[8 + 2 * c], b = n8[9 + 2 * c];
                const uint32_t lo[3] = {a & 255u, (a >> 8) & 255u, (a >> 16) & 255u};
                const uint32_t hi[3] = {a >> 24, b & 255u, (b >> 8) & 255u};
                for (int k = 0; k < 3; ++k) {
                    box.lo[k] = 0.0f + float(lo[k]) * kStep;
                    box.hi[k] = 0.0f + float(hi[k]) * kStep;
                }
                box.ref = n8[4] + (b >> 16);
            } else {
                box = decodeWideChild(t.wide4[node], c);
            }
            if (c == (s & (arity - 1))) fallback = box.ref;
            float tEntry;
            if (!intersectBox(box.lo, box.hi, origin, invDir, FLT_MAX, tEntry)) continue;
            if (hits == 0 || tEntry < best) {  // nearest first, the lower child on ties
                best = tEntry;
                next = box.ref;
            }
            hits |= 1u << c;
        }
        acc += best + float(std::popcount(hits));
        node = ((hits != 0 ? next : fallback) ^ salt) & mask;
    }
    return {acc, float(node)};
}

// One row of a table: a kernel variant with its data, timed in alternation with the others.
struct Case {
    std::string table;     // "small" / "large"
    std::string label;     // the row's name
    std::string group;     // rows whose results must agree exactly ("32", "16", "8", "stack")
    std::string baseline;  // label of the row this one is compared with (same table)
    std::unique_ptr<BenchKernel> bench;
    const HostBuffer* results = nullptr;
    double work = 0;  // node fetches (fetch kernels), traversals (stack kernels) or ray steps (step kernels) per run
    double createSeconds = 0;  // vkCreateComputePipelines and the rest of Bench's set-up
    double firstSeconds = 0;
    std::vector<double> seconds;
    std::vector<float> output;
};

int usage() {
    std::fprintf(stderr,
                 "usage: penumbra_microbench [--runs N] [--invocations N] [--stack-invocations N] [--steps N] "
                 "[--only fetch|stack|step] "
                 "[--spirv-dir DIR]\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 5;
    uint32_t invocations = 1u << 20;
    uint32_t stackInvocations = 1u << 18;  // a traversal is about 40 steps, not 32 cheap ones
    uint32_t steps = 32;
    std::string only;
    std::string spirvDir = PENUMBRA_MICROBENCH_SPIRV_DIR;
    for (int i = 1; i < argc; ++i) {
        std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw std::runtime_error(arg + " needs a value");
            return argv[++i];
        };
        try {
            if (arg == "--runs") runs = std::stoi(value());
            else if (arg == "--invocations") invocations = uint32_t(std::stoul(value()));
            else if (arg == "--stack-invocations") stackInvocations = uint32_t(std::stoul(value()));
            else if (arg == "--steps") steps = uint32_t(std::stoul(value()));
            else if (arg == "--only") only = value();
            else if (arg == "--spirv-dir") spirvDir = value();
            else return usage();
        } catch (const std::exception& e) {
            std::fprintf(stderr, "penumbra_microbench: %s: %s\n", arg.c_str(), e.what());
            return 2;
        }
    }
    if (runs < 1 || invocations < kWorkgroup || invocations % kWorkgroup || stackInvocations < kWorkgroup ||
        stackInvocations % kWorkgroup || steps < 1 ||
        (!only.empty() && only != "fetch" && only != "stack" && only != "step"))
        return usage();

    try {
        Context context;
        const auto& info = context.info();
        std::printf("Device: %s; driver: %s %s; load average at start: %s\n", info.name.c_str(),
                    info.driverName.c_str(), info.driverInfo.c_str(), loadAverage().c_str());
        const auto& limits = context.limits();

        std::map<std::string, Tables> tables;
        tables["small"] = makeTables(kSmallNodes, 1);
        tables["large"] = makeTables(kLargeNodes, 2);
        std::vector<std::unique_ptr<HostBuffer>> buffers;
        std::vector<Case> cases;
        Push push{};
        push.boxScale[0] = push.boxScale[1] = push.boxScale[2] = 1.5f;

        auto addCase = [&](const std::string& table, const std::string& label, const std::string& group,
                           const std::string& baseline, const std::string& kernel, uint32_t specSteps,
                           VkDescriptorType type, const void* data, VkDeviceSize bytes, VkFormat format, Push p,
                           double work, uint32_t threads) {
            VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
            if (type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER) usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
            if (type == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER) usage = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
            if (type == VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER) usage = VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT;
            bool bda = label.find("device address") != std::string::npos;
            if (bda) {
                if (!context.info().bufferDeviceAddress) {
                    std::printf("(skipped %s, %s: no bufferDeviceAddress on this device)\n", table.c_str(),
                                label.c_str());
                    return;
                }
                usage |= VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
            }
            if (type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER && bytes > limits.maxUniformBufferRange) return;
            buffers.push_back(std::make_unique<HostBuffer>(context, data, bytes, usage, format));
            const HostBuffer& nodes = *buffers.back();
            if (bda) {
                p.address[0] = uint32_t(nodes.address());
                p.address[1] = uint32_t(nodes.address() >> 32);
            }
            buffers.push_back(std::make_unique<HostBuffer>(context, nullptr, VkDeviceSize(threads) * 8,
                                                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT));
            Case c;
            c.table = table;
            c.label = label;
            c.group = group;
            c.baseline = baseline;
            c.results = buffers.back().get();
            auto created = std::chrono::steady_clock::now();
            c.bench =
                makeBench(context, spirvDir + "/" + kernel + ".spv", specSteps, type, nodes, *c.results, p, threads);
            c.createSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - created).count();
            c.work = work;
            cases.push_back(std::move(c));
        };

        const auto SSBO = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, UBO = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                   TEXEL = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, IMAGE = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
        const auto F32 = VK_FORMAT_R32G32B32A32_SFLOAT, U32 = VK_FORMAT_R32G32B32A32_UINT,
                   U32x2 = VK_FORMAT_R32G32_UINT, NONE = VK_FORMAT_UNDEFINED;
        const std::string base = "(a) storage buffer";
        if (only.empty() || only == "fetch") {
            for (const std::string table : {"small", "large"}) {
                const Tables& t = tables[table];
                uint32_t count = uint32_t(t.nodes8.size() / 2);
                Push p = push;
                p.mask = count - 1;
                double work = double(invocations) * steps;
                VkDeviceSize b32 = t.nodes32.size() * 4, b16 = t.nodes16.size() * 4, b8 = t.nodes8.size() * 4;
                const void *d32 = t.nodes32.data(), *d16 = t.nodes16.data(), *d8 = t.nodes8.data();
                bool small = table == "small";
                addCase(table, base, "32", base, "fetch_ssbo", steps, SSBO, d32, b32, NONE, p, work, invocations);
                if (small)
                    addCase(table, "(b) uniform buffer", "32", base, "fetch_ubo", steps, UBO, d32, b32, NONE, p, work,
                            invocations);
                if (2ull * count <= limits.maxTexelBufferElements) {
                    addCase(table, "(c) texel buffer RGBA32F, texelFetch", "32", base, "fetch_texel", steps, TEXEL, d32,
                            b32, F32, p, work, invocations);
                    addCase(table, "(c') storage texel buffer RGBA32F, imageLoad", "32", base, "fetch_image", steps,
                            IMAGE, d32, b32, F32, p, work, invocations);
                }
                if (small && b32 <= limits.maxComputeSharedMemorySize)
                    addCase(table, "(d) shared memory, copied in per workgroup of 64", "32", base, "fetch_shared",
                            steps, SSBO, d32, b32, NONE, p, work, invocations);
                addCase(table, "(e) buffer device address", "32", base, "fetch_bda", steps, SSBO, d32, b32, NONE, p,
                        work, invocations);
                // The renderer's reads on Mesa 25 (render/node_reads.h): a 32-byte node in one
                // u64vec4 load, from the binding or through the address.
                if (context.info().shaderInt64) {
                    addCase(table, "(a64) storage buffer, one u64vec4 load", "32", base, "fetch_ssbo64", steps, SSBO,
                            d32, b32, NONE, p, work, invocations);
                    addCase(table, "(e64) buffer device address, one u64vec4 load", "32", base, "fetch_bda64", steps,
                            SSBO, d32, b32, NONE, p, work, invocations);
                }
                addCase(table, "(f) 16-byte node (8-bit planes), storage buffer", "16", base, "fetch_packed16_ssbo",
                        steps, SSBO, d16, b16, NONE, p, work, invocations);
                if (small)
                    addCase(table, "(f) 16-byte node, uniform buffer", "16", base, "fetch_packed16_ubo", steps, UBO,
                            d16, b16, NONE, p, work, invocations);
                addCase(table, "(f) 16-byte node, texel buffer RGBA32UI", "16", base, "fetch_packed16_texel", steps,
                        TEXEL, d16, b16, U32, p, work, invocations);
                addCase(table, "(f) 8-byte node (5-bit planes), storage buffer", "8", base, "fetch_packed8_ssbo", steps,
                        SSBO, d8, b8, NONE, p, work, invocations);
                addCase(table, "(f) 8-byte node, texel buffer RG32UI", "8", base, "fetch_packed8_texel", steps, TEXEL,
                        d8, b8, U32x2, p, work, invocations);
            }
        }
        if (only.empty() || only == "stack") {
            // Depth 9 (1,023 nodes, 32 KiB) and 19 (1M nodes); each child is visited with a
            // probability that makes a traversal visit about 40 nodes.
            for (const auto& [table, depth, probability] :
                 {std::tuple{std::string("small"), 9u, 0.65}, std::tuple{std::string("large"), 19u, 0.535}}) {
                const Tables& t = tables[table];
                Push p = push;
                p.threshold = uint32_t(probability * 65536.0);
                const std::string local = "local array[64]";
                VkDeviceSize bytes = t.nodes32.size() * 4;
                std::string name = table + " tree";
                addCase(name, local, "stack", local, "stack_local", depth, SSBO, t.nodes32.data(), bytes, NONE, p,
                        stackInvocations, stackInvocations);
                addCase(name, "shared memory, 64 entries per invocation", "stack", local, "stack_shared", depth, SSBO,
                        t.nodes32.data(), bytes, NONE, p, stackInvocations, stackInvocations);
                addCase(name, "short stack (4-entry ring) + restart trail", "stack", local, "stack_short", depth, SSBO,
                        t.nodes32.data(), bytes, NONE, p, stackInvocations, stackInvocations);
                addCase(name, "restart trail, no stack", "stack", local, "stack_trail", depth, SSBO, t.nodes32.data(),
                        bytes, NONE, p, stackInvocations, stackInvocations);
            }
        }

        // Steps: one ray per invocation on four-wide nodes against a node's eight children
        // across eight invocations (step.comp), the tables about equal in bytes.
        std::map<std::string, StepTables> stepTables;
        const std::string raysLabel = "rays across lanes, 4-wide nodes (device address)";
        if (only.empty() || only == "step") {
            VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
            VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
            properties.pNext = &subgroup;
            vkGetPhysicalDeviceProperties2(context.physicalDevice(), &properties);
            const bool shuffles = subgroup.subgroupSize >= 8 &&
                                  (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                                  (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_SHUFFLE_BIT);
            if (!context.info().shaderInt64) {
                std::printf("(skipped the steps: no shaderInt64 on this device)\n");
            } else {
                stepTables["small"] = makeStepTables(512, 256, 3);            // 32 KiB and 24 KiB
                stepTables["large"] = makeStepTables(1u << 19, 1u << 18, 4);  // 32 MiB and 24 MiB
                for (const std::string table : {"small", "large"}) {
                    const StepTables& t = stepTables[table];
                    Push p = push;
                    p.mask = t.count4 - 1;
                    const VkDeviceSize bytes4 = t.wide4.size() * sizeof(gpu::WideNode);
                    addCase(table, raysLabel, "step4", raysLabel, "step_rays", steps, SSBO, t.wide4.data(), bytes4,
                            NONE, p, double(invocations) * steps, invocations);
                    addCase(table, "rays across lanes, 4-wide nodes of float planes (device address)", "step4",
                            raysLabel, "step_rays_float", steps, SSBO, t.wide4Float.data(), t.wide4Float.size() * 4,
                            NONE, p, double(invocations) * steps, invocations);
                    // Every node's frame: its base, the exponents, all four children.
                    Push frame = p;
                    frame.boxOrigin[0] = frame.boxOrigin[1] = frame.boxOrigin[2] = kWideBase;
                    frame.threshold = kWideExponents | gpu::WIDE_ALL_CHILDREN << gpu::WIDE_CHILD_MASK_SHIFT;
                    addCase(table, "rays across lanes, 4-wide nodes, frame not loaded (device address)", "step4",
                            raysLabel, "step_rays_no_frame", steps, SSBO, t.wide4.data(), bytes4, NONE, frame,
                            double(invocations) * steps, invocations);
                    addCase(table, "rays across lanes, 4-wide nodes, next nodes touched early (device address)",
                            "step4", raysLabel, "step_rays_prefetch", steps, SSBO, t.wide4.data(), bytes4, NONE, p,
                            double(invocations) * steps, invocations);
                    addCase(table, "two rays per invocation, interleaved (device address)", "step4 pair", raysLabel,
                            "step_rays_pair", steps, SSBO, t.wide4.data(), bytes4, NONE, p, 2.0 * invocations * steps,
                            invocations);
                    addCase(table, "four rays per invocation, interleaved (device address)", "step4 quad", raysLabel,
                            "step_rays_quad", steps, SSBO, t.wide4.data(), bytes4, NONE, p, 4.0 * invocations * steps,
                            invocations);
                    if (!shuffles) {
                        std::printf("(skipped %s, 8-wide steps: subgroups of fewer than 8 lanes or no shuffles)\n",
                                    table.c_str());
                        continue;
                    }
                    p.mask = t.count8 - 1;
                    addCase(table, "a node's children across lanes, 8-wide nodes (device address)", "step8", raysLabel,
                            "step_children8", steps, SSBO, t.wide8.data(), t.wide8.size() * 4, NONE, p,
                            double(invocations) / 8.0 * steps, invocations);
                    addCase(table, "the same without the shuffles, each lane alone (device address)", "step8 alone",
                            raysLabel, "step_children8_alone", steps, SSBO, t.wide8.data(), t.wide8.size() * 4, NONE, p,
                            double(invocations) / 8.0 * steps, invocations);
                }
            }
        }

        // First dispatch (llvmpipe compiles the kernel here or at pipeline creation: "compile
        // s" is the creation time plus the first dispatch's excess over the median), then
        // `runs` rounds in which
        // every case runs once, so that load changes on the machine hit all alike.
        for (auto& c : cases) c.firstSeconds = c.bench->run();
        for (int r = 0; r < runs; ++r)
            for (auto& c : cases) c.seconds.push_back(c.bench->run());
        for (auto& c : cases) {
            const float* out = static_cast<const float*>(c.results->data());
            c.output.assign(out, out + size_t(c.results->size() / sizeof(float)));
        }

        // Results that must agree: every 32-byte source with (a), each packed layout with its
        // storage-buffer version, every stack with the local array (sums only).
        std::map<std::string, const Case*> firstOfGroup;
        bool allAgree = true;
        for (const auto& c : cases) {
            std::string key = c.table + "/" + c.group;
            auto [it, inserted] = firstOfGroup.emplace(key, &c);
            if (inserted) continue;
            const auto& ref = it->second->output;
            bool same = true;
            for (size_t i = 0; i < ref.size(); i += (c.group == "stack" ? 2 : 1))
                if (std::bit_cast<uint32_t>(ref[i]) != std::bit_cast<uint32_t>(c.output[i]))
                    same = false;  // bit-identical
            if (!same) {
                std::printf("MISMATCH: %s, %s computed other results than %s\n", c.table.c_str(), c.label.c_str(),
                            it->second->label.c_str());
                allAgree = false;
            }
        }

        auto baselineRate = [&](const Case& c) {
            for (const auto& o : cases)
                if (o.table == c.table && o.label == c.baseline) return o.work / median(o.seconds);
            return 0.0;
        };
        bool header = false;
        for (const auto& c : cases) {
            if (c.group == "stack" || c.group.rfind("step", 0) == 0) continue;
            if (!header) {
                std::printf("\nNode fetches in a divergent walk: %u invocations x %u steps, median of %d runs\n\n",
                            invocations, steps, runs);
                std::printf("| table | source | M node fetches/s | vs (a) | compile s |\n|---|---|---|---|---|\n");
                header = true;
            }
            double rate = c.work / median(c.seconds);
            std::printf("| %s (%s nodes) | %s | %.0f | %.2f | %.3f |\n", c.table.c_str(),
                        c.table == "small" ? "1,024" : "1,048,576", c.label.c_str(), rate / 1e6, rate / baselineRate(c),
                        c.createSeconds + std::max(0.0, c.firstSeconds - median(c.seconds)));
        }
        header = false;
        for (const auto& c : cases) {
            if (c.group != "stack") continue;
            if (!header) {
                std::printf(
                    "\nTraversal stack: %u traversals of a binary tree, nodes from a storage buffer, median of %d "
                    "runs\n\n",
                    stackInvocations, runs);
                std::printf(
                    "| tree | stack | M traversals/s | nodes fetched per traversal | M node fetches/s | vs local array "
                    "| compile s |\n|---|---|---|---|---|---|---|\n");
                header = true;
            }
            double fetches = 0;
            for (size_t i = 1; i < c.output.size(); i += 2) fetches += c.output[i];
            double seconds = median(c.seconds);
            double rate = c.work / seconds;
            std::printf("| %s (depth %s) | %s | %.2f | %.1f | %.0f | %.2f | %.3f |\n", c.table.c_str(),
                        c.table == "small tree" ? "9" : "19", c.label.c_str(), rate / 1e6, fetches / c.work,
                        fetches / seconds / 1e6, rate / baselineRate(c),
                        c.createSeconds + std::max(0.0, c.firstSeconds - seconds));
        }
        header = false;
        for (const auto& c : cases) {
            if (c.group.rfind("step", 0) != 0) continue;
            const bool children8 = c.group == "step8";
            if (!header) {
                std::printf(
                    "\nTraversal steps: %u invocations x %u steps (8-wide: eight invocations a ray), nodes "
                    "through their device address, median of %d runs\n\n",
                    invocations, steps, runs);
                std::printf(
                    "| table | mapping | M ray steps/s | M box tests/s | vs rays | compile s |\n"
                    "|---|---|---|---|---|---|\n");
                header = true;
            }
            // The first 256 rays against their walk replayed on the CPU, bit for bit (the
            // lanes that go alone walk no ray's path).
            const StepTables& t = stepTables.at(c.table);
            // Invocation i of a pair: ray 2i's sum, ray 2i + 1's node; of a quad: 4i's and 4i + 3's.
            const uint32_t raysPer = c.group == "step4 pair" ? 2 : (c.group == "step4 quad" ? 4 : 1);
            for (uint32_t ray = 0; ray < (c.group == "step8 alone" ? 0u : 256u); ++ray) {
                const size_t at = 2 * size_t(children8 ? 8 * ray : ray);
                const float acc = replayStep(t, children8, raysPer * ray, steps).first;
                const float node = replayStep(t, children8, raysPer * ray + raysPer - 1, steps).second;
                if (std::bit_cast<uint32_t>(acc) != std::bit_cast<uint32_t>(c.output[at]) || node != c.output[at + 1]) {
                    std::printf("MISMATCH: %s, %s: ray %u walked otherwise than on the CPU\n", c.table.c_str(),
                                c.label.c_str(), ray);
                    allAgree = false;
                    break;
                }
            }
            const double seconds = median(c.seconds), rate = c.work / seconds;
            std::printf("| %s (%s) | %s | %.1f | %.0f | %.2f | %.3f |\n", c.table.c_str(),
                        c.table == "small" ? "32 / 24 KiB" : "32 / 24 MiB", c.label.c_str(), rate / 1e6,
                        rate * (c.group.rfind("step4", 0) == 0 ? 4 : 8) / 1e6, rate / baselineRate(c),
                        c.createSeconds + std::max(0.0, c.firstSeconds - seconds));
        }
        std::printf("\nLoad average at the end: %s. Results agree across variants: %s\n", loadAverage().c_str(),
                    allAgree ? "yes" : "NO");
        return allAgree ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra_microbench: %s\n", e.what());
        return 1;
    }
}
