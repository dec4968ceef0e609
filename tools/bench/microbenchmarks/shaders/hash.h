// Chris Wellons' "lowbias32" integer hash (hash-prospector, 2018): cheap and well
// distributed, so per-lane indices differ. Shared by the kernels (common.glsl: hash) and
// microbench.cpp, which replays the step kernels' walks on the CPU.
#ifndef MICROBENCH_HASH_H
#define MICROBENCH_HASH_H

#ifdef __cplusplus
#include <cstdint>
inline uint32_t lowbias32(uint32_t x)
#else
uint hash(uint x)
#endif
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

#endif
