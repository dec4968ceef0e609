// Where the traversal reads BVH nodes from on a given device (SPEC_NODE_READS,
// shaders/geometry/bvh.glsl): a texel buffer or a storage buffer holding the same bytes, or
// that buffer through its device address.
// Measured on lavapipe (docs/performance-history/round-10.md): Mesa 22.3 compiles a texel fetch
// into an inline gather and a storage-buffer load inside the traversal loop into a loop
// over the SIMD lanes, and renders a million triangles 1.23-1.35x faster from texels;
// Mesa 25.0 compiles the texel fetch into an indirect call, and the storage buffer is
// 1.23-1.42x faster there on a million triangles (1.07x on the mesh-light scene), and
// faster again, 1.07-1.10x (docs/performance-history/round-11.md), read in two loads of 32 bytes instead of four of
// 16 where the device has 64-bit integers (the kernels' "_int64" variants), and faster again,
// 1.06-1.17x (docs/performance-history/round-12.md), with the same loads made through the buffer's device address,
// which lavapipe 25.0 compiles into hardware gathers (the "_address" variants).
#pragma once

#include <cstdint>
#include <string>

#include "gpu/context.h"

namespace penumbra {

// How the render kernels read nodes.
enum class NodeReads {
    Device,     // what nodeReadsFor says for the device (every render)
    Texels,     // always the texel buffer (benchmarks compare)
    Storage,    // always the storage buffer, in loads of 16 bytes
    Storage32,  // the storage buffer in loads of 32 bytes where the device has shaderInt64,
                // else of 16
    Address,    // loads of 32 bytes through the buffer's device address where the device has
                // shaderInt64 and bufferDeviceAddress, else as Storage32
};

// NODE_READS_TEXELS for lavapipe before Mesa 25 (its driverInfo names the version,
// "Mesa 22.3.6 (LLVM 15.0.6)"), the storage buffer for every other device: later lavapipes,
// and GPUs, whose usual path storage buffers are; NODE_READS_STORAGE_32 where the device
// has shaderInt64, else NODE_READS_STORAGE. Later lavapipes with shaderInt64 and
// bufferDeviceAddress get NODE_READS_ADDRESS (on GPUs it is not measured).
uint32_t nodeReadsFor(const gpu::DeviceInfo& device);

// The SPEC_NODE_READS value `mode` gives on `device`.
uint32_t nodeReadsValue(NodeReads mode, const gpu::DeviceInfo& device);

// The major version in a Mesa driverInfo string ("Mesa 25.0.7 (LLVM 15.0.6)" -> 25), or 0
// where the string names none.
int mesaMajorVersion(const std::string& driverInfo);

// The name of the kernel `base` ("integrators/direct") that reads nodes as `nodeReads` says:
// "<base>_int64" for NODE_READS_STORAGE_32, "<base>_address" for NODE_READS_ADDRESS, else
// `base`.
std::string nodeReadsKernel(const std::string& base, uint32_t nodeReads);

}  // namespace penumbra
