// Lockstep replay of recorded traversal rounds (lane_replay.h says what each form costs).
#include "bvh/lane_replay.h"

#include <algorithm>
#include <cstddef>

namespace penumbra {

namespace {

uint32_t descentOf(uint32_t round) { return round >> 16; }
uint32_t leafOf(uint32_t round) { return round & 0xffffu; }

}  // namespace

void LaneUse::addGroup(const std::vector<const LaneRays*>& lanes) {
    size_t roundCount = 0;
    for (const LaneRays* lane : lanes) {
        rays += lane->rays;
        for (uint32_t r : lane->rounds) {
            nodes += descentOf(r);
            primitives += leafOf(r);
        }
        roundCount = std::max(roundCount, lane->rounds.size());
    }
    // while-while: round k runs the longest descent and then the longest leaf of the lanes
    // that still have a round k.
    for (size_t k = 0; k < roundCount; ++k) {
        uint32_t descent = 0, leaf = 0;
        for (const LaneRays* lane : lanes)
            if (k < lane->rounds.size()) {
                descent = std::max(descent, descentOf(lane->rounds[k]));
                leaf = std::max(leaf, leafOf(lane->rounds[k]));
            }
        whileNodes += descent;
        whilePrimitives += leaf;
    }
    // if-if: each lane's node steps and primitive tests in the order it makes them, one per
    // iteration; walk the lanes' sequences side by side without spelling them out.
    struct Cursor {
        size_t round = 0;
        uint32_t done = 0;  // steps taken in this round (its descent first, then its leaf)
    };
    std::vector<Cursor> cursors(lanes.size());
    while (true) {
        bool anyNode = false, anyPrimitive = false;
        for (size_t i = 0; i < lanes.size(); ++i) {
            const std::vector<uint32_t>& rounds = lanes[i]->rounds;
            Cursor& c = cursors[i];
            // Skip rounds with nothing (left) to do.
            while (c.round < rounds.size() && c.done >= descentOf(rounds[c.round]) + leafOf(rounds[c.round])) {
                ++c.round;
                c.done = 0;
            }
            if (c.round == rounds.size()) continue;
            (c.done < descentOf(rounds[c.round]) ? anyNode : anyPrimitive) = true;
            ++c.done;
        }
        if (!anyNode && !anyPrimitive) break;
        ifNodes += anyNode ? 1 : 0;
        ifPrimitives += anyPrimitive ? 1 : 0;
    }
}

}  // namespace penumbra
