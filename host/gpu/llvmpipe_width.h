// How many SIMD lanes llvmpipe (lavapipe's code generator) gives a kernel: 8 (256-bit
// vectors) by default, 16 where LP_NATIVE_VECTOR_WIDTH=512 asks for them. The choice is an
// environment variable that the driver reads when it loads, so it is made before the
// Vulkan instance exists (gpu/context.cpp); other drivers ignore it.
#pragma once

namespace penumbra::gpu {

// For its lifetime, LP_NATIVE_VECTOR_WIDTH=512 on Intel CPUs with AVX-512 (F, BW, DQ, VL),
// unless the variable is set already or the context will present to a window. There, 16
// lanes rendered 1.30x the samples per second on a million triangles and 1.18x on the
// Cornell box, where an AMD EPYC (Zen 4, whose AVX-512 runs a 512-bit operation in two
// halves) measured 0.91-1.01x (docs/PERFORMANCE.md, "Round 22"). Images are the same bit
// for bit: each lane computes what it did. The preview keeps 8 lanes: with 16, llvmpipe
// 25.0.7 stops it with a bus error while it presents. The variable is taken back when this
// ends (once the device exists, the driver has read it), so that the processes this one
// starts, the preview among them, choose for themselves.
class LlvmpipeWidthChoice {
public:
    explicit LlvmpipeWidthChoice(bool presents);
    ~LlvmpipeWidthChoice();
    LlvmpipeWidthChoice(const LlvmpipeWidthChoice&) = delete;
    LlvmpipeWidthChoice& operator=(const LlvmpipeWidthChoice&) = delete;

private:
    bool m_set = false;
};

}  // namespace penumbra::gpu
