// The lockstep replay behind penumbra_bench --lanes (bvh/lane_replay.h): what a SIMD group
// runs for its lanes' recorded rounds, in the while-while and the if-if loop.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/lane_replay.h"

using namespace penumbra;

namespace {

uint32_t round(uint32_t nodes, uint32_t primitives) { return nodes << 16 | primitives; }

}  // namespace

TEST(LaneReplay, WhileWhilePaysTheLongestDescentAndLeafOfEachRound) {
    // Lane A: one ray, a descent of 4 nodes to a leaf of 1 primitive. Lane B: two rays, each
    // a descent of 1 to a leaf of 1, the second one taken when the first is done.
    LaneRays a{1, {round(4, 1)}}, b{2, {round(1, 1), round(1, 1)}};
    LaneUse use;
    use.addGroup({&a, &b});
    EXPECT_EQ(use.rays, 3);
    EXPECT_EQ(use.nodes, 6);
    EXPECT_EQ(use.primitives, 3);
    // Round 0: max(4, 1) nodes, max(1, 1) primitives; round 1: B alone.
    EXPECT_EQ(use.whileNodes, 5);
    EXPECT_EQ(use.whilePrimitives, 2);
    // One op per iteration: A n n n n p, B n p n p. Iterations 0-3 step a node; 1, 3 and 4
    // test a primitive.
    EXPECT_EQ(use.ifNodes, 4);
    EXPECT_EQ(use.ifPrimitives, 3);
    EXPECT_DOUBLE_EQ(use.whileNodeShare(), 6.0 / (8.0 * 5.0));
    EXPECT_DOUBLE_EQ(use.ifPrimitiveShare(), 3.0 / (8.0 * 3.0));
}

TEST(LaneReplay, RoundsWithoutALeafCostNoPrimitiveTest) {
    // A descent that finds no child hit ends its round with an empty leaf: the if-if loop
    // goes straight on to the lane's next round.
    LaneRays a{1, {round(2, 0), round(1, 2)}}, b{1, {round(3, 0)}};
    LaneUse use;
    use.addGroup({&a, &b});
    EXPECT_EQ(use.whileNodes, 3 + 1);
    EXPECT_EQ(use.whilePrimitives, 0 + 2);
    // A: n n n p p; B: n n n.
    EXPECT_EQ(use.ifNodes, 3);
    EXPECT_EQ(use.ifPrimitives, 2);
}

TEST(LaneReplay, EqualLanesFillTheWidthAndALoneLaneAnEighth) {
    const LaneRays ray{1, {round(5, 3), round(2, 0), round(4, 4)}};
    LaneUse full, alone;
    full.addGroup(std::vector<const LaneRays*>(8, &ray));
    alone.addGroup({&ray});
    for (const LaneUse* use : {&full, &alone}) {
        const double expected = use == &full ? 1.0 : 0.125;
        EXPECT_DOUBLE_EQ(use->whileNodeShare(), expected);
        EXPECT_DOUBLE_EQ(use->whilePrimitiveShare(), expected);
        EXPECT_DOUBLE_EQ(use->ifNodeShare(), expected);
        EXPECT_DOUBLE_EQ(use->ifPrimitiveShare(), expected);
    }
}
