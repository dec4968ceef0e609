// Kernels as shader objects (VK_EXT_shader_object) instead of compute pipelines, on the
// devices where that lets a process take a kernel's driver binary back from disk
// (gpu/kernel_binaries.h): lavapipe. There a binary is the kernel's optimised NIR, and
// taking it back skips SPIR-V to NIR, function inlining and NIR's optimisation loop, which
// were most of a small render's start-up time and all of its peak memory
// (docs/PERFORMANCE.md, "Start-up"). Mesa's own disk cache then serves the LLVM step as
// before. The kernel compiled is the same either way: a shader object from SPIR-V runs the
// same lowering as a pipeline, and a binary is that lowering's result.
//
// Other devices keep compute pipelines: their drivers cache whole pipelines themselves.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.h"

namespace penumbra::gpu {

// Whether the Context makes kernels shader objects on this device: llvmpipe (lavapipe)
// with the shaderObject feature (Mesa 23.1 and later; 22.3 keeps pipelines).
bool kernelsAsShaderObjects(const DeviceInfo& info);

// How a shader object was made, for the tests and tools/bench/bench/startup.
enum class ShaderObjectSource { Compiled, FromDisk };

// A compute shader object of `spirv` with constant_id i = specialization[i] (applied before
// the driver sees it: gpu/spirv_specialization.h), descriptor set 0 laid out as `setLayout`
// and `pushConstantBytes` of push constants: taken from the kernel binaries on disk where
// one matches (then the SPIR-V is not even specialized), else compiled and stored there.
// Throws GpuError (naming `what`) if it cannot be made.
VkShaderEXT createComputeShaderObject(const Context& context, std::span<const uint32_t> spirv,
                                      const std::vector<uint32_t>& specialization, VkDescriptorSetLayout setLayout,
                                      uint32_t pushConstantBytes, const std::string& what,
                                      ShaderObjectSource* source = nullptr);

}  // namespace penumbra::gpu
