// The SIMD width llvmpipe compiles kernels for (see llvmpipe_width.h).
#include "gpu/llvmpipe_width.h"

#include <cstdlib>

namespace penumbra::gpu {

namespace {
constexpr const char* kVariable = "LP_NATIVE_VECTOR_WIDTH";
}

LlvmpipeWidthChoice::LlvmpipeWidthChoice(bool presents) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    if (presents || std::getenv(kVariable) != nullptr) return;  // the user's choice stands
    __builtin_cpu_init();
    const bool avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
    if (avx512 && __builtin_cpu_is("intel")) m_set = setenv(kVariable, "512", 0) == 0;
#else
    (void)presents;
#endif
}

LlvmpipeWidthChoice::~LlvmpipeWidthChoice() {
    if (m_set) unsetenv(kVariable);
}

}  // namespace penumbra::gpu
