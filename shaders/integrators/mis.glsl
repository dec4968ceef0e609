// Multiple importance sampling weights (Veach & Guibas 1995; lecture, "Multiple Importance
// Sampling"; PBR book 3rd ed. 14.3.1): for strategy s with N_s samples and density p_s,
//   balance  w_s = N_s p_s / sum_j N_j p_j
//   power    w_s = (N_s p_s)^2 / sum_j (N_j p_j)^2
// Written as 1 / (1 + r^k) with r = other / own so that huge densities cannot overflow.
#ifndef PENUMBRA_MIS_GLSL
#define PENUMBRA_MIS_GLSL

#include "shared/types.h"

// `own` = N_s p_s of the strategy that drew the sample, `other` = N_t p_t of the other one.
float misWeight(float own, float other, uint heuristic) {
    if (!(own > 0.0)) return 0.0;
    float r = other / own;
    if (heuristic == HEURISTIC_POWER) r *= r;
    return 1.0 / (1.0 + r);
}

#endif
