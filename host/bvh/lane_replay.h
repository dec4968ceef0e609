// The SIMD-lane model behind penumbra_bench --lanes: rays recorded by the CPU mirror of the
// traversal (bvh/traverse.cpp, TraversalWork::rounds) replayed in lockstep, eight lanes at a
// time, as llvmpipe runs the kernel's loops: a loop runs until its last lane is done, and a
// branch costs its code whenever any lane takes it. Two loop forms are replayed on the same
// rays, so that one run says what each would use of the SIMD width:
//
// - while-while (the kernel's form, geometry/bvh.glsl): round k of the outer loop costs the
//   largest descent of the lanes' round k plus their largest leaf.
// - if-if (Aila & Laine 2009, section 3): one loop whose iteration takes one node step or
//   one primitive test per lane; an iteration costs a node step if any lane steps a node
//   and a primitive test if any lane tests one.
//
// A lane may trace several rays one after another (its rounds concatenated): a lane whose
// ray is done takes its next ray at the next round (while-while) or iteration (if-if), the
// refill of finished lanes that persistent-thread traversal does. The set-up of a new ray
// is left out, so the refill's figures are an upper bound.
#ifndef PENUMBRA_BVH_LANE_REPLAY_H
#define PENUMBRA_BVH_LANE_REPLAY_H

#include <cstdint>
#include <vector>

namespace penumbra {

// The rays one SIMD lane traces, one after another.
struct LaneRays {
    uint32_t rays = 0;
    std::vector<uint32_t> rounds;  // TraversalWork::rounds of each ray, concatenated
};

// Node steps and primitive tests of the lanes' rays, and what their groups ran for them in
// each loop form. A share is what the lanes did over eight times what their groups ran.
struct LaneUse {
    double rays = 0, nodes = 0, primitives = 0;
    double whileNodes = 0, whilePrimitives = 0;  // node steps and primitive tests the groups ran, while-while
    double ifNodes = 0, ifPrimitives = 0;        // the same, if-if

    // One SIMD group: at most eight lanes (fewer where a row of the film or a queue ends; the
    // group is still eight wide).
    void addGroup(const std::vector<const LaneRays*>& lanes);

    double whileNodeShare() const { return share(nodes, whileNodes); }
    double whilePrimitiveShare() const { return share(primitives, whilePrimitives); }
    double ifNodeShare() const { return share(nodes, ifNodes); }
    double ifPrimitiveShare() const { return share(primitives, ifPrimitives); }

private:
    static double share(double done, double ran) { return ran > 0 ? done / (8.0 * ran) : 0.0; }
};

}  // namespace penumbra

#endif
