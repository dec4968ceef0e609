// How many SIMD lanes llvmpipe (lavapipe's code generator) gives a kernel: 8 (256-bit
// vectors) by default, 16 where LP_NATIVE_VECTOR_WIDTH=512 asks for them. Whether 16 pay
// depends on the CPU and on the driver's version (docs/performance-history/round-23.md):
//
//   CPU                         Mesa 22.3.6          Mesa 25.0.7                 Mesa 26.2.6
//   Intel Xeon, AVX-512         0.016x (60x slower)  1.15-1.33x, same images     aborts on BVH scenes
//   AMD EPYC Zen 4, AVX-512     -                    0.91-1.01x                  -
//
// The variable is read when the driver loads (its shader cache, its device name) and again
// at every kernel compile, so the choice must be made before the Vulkan instance that
// renders exists, while the driver's version is only known once some instance exists. So
// gpu::Context asks a first, short-lived instance for the version (chooseLlvmpipeWidth in
// gpu/context.cpp), and only then sets the variable and creates its own.
#pragma once

#include <string>

namespace penumbra::gpu {

// A Mesa version as VkPhysicalDeviceDriverProperties::driverInfo gives it for llvmpipe
// ("Mesa 25.0.7 - kisak-mesa PPA (LLVM 19.1.7)", "Mesa 22.3.6 (LLVM 15.0.6)").
struct MesaVersion {
    int major = 0;
    int minor = 0;
    bool known() const { return major > 0; }
};
// The version in `driverInfo`, or an unknown one (major 0) when it names no Mesa version.
MesaVersion parseMesaVersion(const std::string& driverInfo);

// True where 16 lanes were measured faster: an Intel CPU with AVX-512 (F, BW, DQ, VL) and
// llvmpipe from the Mesa 25.0 series. Other releases (22.3 renders 60x slower at 16 lanes,
// 26.2 aborts: "stack smashing detected") and other CPUs keep the driver's own 8 until
// measured.
bool sixteenLanesPay(bool intelWithAvx512, const std::string& driverName, const std::string& driverInfo);

// Whether this CPU is an Intel one with AVX-512 F, BW, DQ and VL.
bool cpuIsIntelWithAvx512();

// The width choice as this process's environment leaves it open.
// - A penumbra that started this one (the preview from the tests, renders from `batch`)
//   passes its choice on, marked by PENUMBRA_LLVMPIPE_WIDTH: the marked variables are
//   removed here, once per process, so that each process chooses for itself.
// - Returns false where the choice is not penumbra's or cannot pay: the user set
//   LP_NATIVE_VECTOR_WIDTH or MESA_SHADER_CACHE_DIR; the context presents (with 16 lanes,
//   llvmpipe 25.0.7 stops the preview with a bus error while presenting); the CPU is not
//   an Intel one with AVX-512; there is no cache directory to give the 16-lane kernels
//   (below) or it cannot be made a directory; or a choice was made already in this process.
bool llvmpipeWidthChoiceOpen(bool presents);

// Sets LP_NATIVE_VECTOR_WIDTH=512 for the rest of the process with a shader cache of its
// own, MESA_SHADER_CACHE_DIR = $XDG_CACHE_HOME (or ~/.cache)/penumbra/llvmpipe-512: Mesa
// 25.0.7's cache does not key kernels by the width, so a process at one width would load
// what one at the other compiled (measured as slow as 8 lanes; once, a garbled image).
void askForSixteenLanes();

}  // namespace penumbra::gpu
