// The binary tree of build.cpp collapsed into the four-wide, quantized nodes the traversal
// reads (gpu::WideNode in shared/types.h; shaders/geometry/bvh.glsl, traverse.cpp).
//
// Collapsing: each wide node stands for a binary interior node, and its (up to four)
// children are binary nodes below it that cover its subtree: its two children, or nodes
// found by opening interior ones into their two children. Which to open:
// - WideCollapse::Optimal (the default) picks, over the whole tree, the covers that give the
//   least total surface area of the wide nodes: the SAH cost of the node steps (the leaves
//   are the binary tree's whatever is opened, so their cost is fixed). A dynamic programme
//   over the binary tree, bottom up: D(n, k), the least area of wide nodes covering n's
//   subtree in at most k child slots, is 0 for a leaf, and for an interior node the better
//   of making n a wide node, W(n) = A(n) + min_j D(l, j) + D(r, 4 - j), and of opening it,
//   min_j D(l, j) + D(r, k - j). The same idea as Ylitie, Karras & Laine 2017, section 3.2,
//   for eight-wide nodes; with four and leaves kept whole it needs no leaf term.
// - WideCollapse::Greedy opens, while a node has fewer than four children, the interior
//   child of largest surface area (Wald et al. 2008, "Getting Rid of Packets", and Embree's
//   BVH4 builder: the large boxes are the ones most rays test).
// On the 1M-triangle bench scene the optimal collapse takes 4% fewer node steps per camera
// ray and 2% per AO ray, about a fifth fewer wide nodes (64.6 -> 61.1 bytes of geometry
// per triangle), and 1.2% fewer instructions per sample (docs/performance-history/round-16.md).
// Either way every wide child is at least one binary level below its parent, so the wide
// tree is no deeper than the binary one (at most BVH_MAX_DEPTH), which bounds the
// traversal stack.
//
// Quantizing: Ylitie, Karras & Laine 2017, section 3.1, with one exponent per axis and node.
#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <string>

#include "bvh/bvh.h"

namespace penumbra {

namespace {

// A plane of an axis of a wide node (shared/types.h): base + the float whose exponent field
// is E and whose mantissa holds q in bits 8-15, 2^(E - 127) + q * 2^(E - 142). That float
// is exact, and one rounding follows, in the sum, as in the shader.
float planeOf(float base, uint32_t exponent, uint32_t q) {
    return base + std::bit_cast<float>(exponent << 23 | q << 8);
}

// An axis of a node's frame: the base and the exponent E of the planes over [lo, hi].
struct AxisFrame {
    float base = 0.0f;
    uint32_t exponent = 1;
};

// The smallest exponent E (1 to 254) whose planes reach from lo past hi in 255 steps of
// 2^(E - 142), and its base: lo - 2^(E - 127), rounded to a float, then lowered a float at a
// time until its plane 0 is at most lo. So q_lo = 0 and q_hi = 255 always contain [lo, hi].
// Throws std::invalid_argument where no exponent reaches: an extent beyond about 1e36,
// which no scene within limits.h's ranges has (the commands report it as an error).
AxisFrame frameFor(float lo, float hi) {
    uint32_t e = 1;
    const double extent = double(hi) - double(lo);
    if (extent > 0.0) {
        int exponent;
        std::frexp(extent / 255.0, &exponent);  // extent / 255 < 2^exponent
        e = uint32_t(std::clamp(exponent - 1 + 142, 1, 254));
    }
    for (; e <= 254; ++e) {
        float base = float(double(lo) - std::ldexp(1.0, int(e) - 127));
        while (planeOf(base, e, 0) > lo) base = std::nextafter(base, -FLT_MAX);
        if (planeOf(base, e, 255) >= hi) return {base, e};
    }
    throw std::invalid_argument("makeWideNodes: a node's extent (" + std::to_string(extent) +
                                ") is too large for its quantized planes");
}

// One plane of one child: q with planeOf(q) <= value (lower planes) or >= value (upper
// planes), as tight as the byte allows. The planes grow with q.
uint32_t quantize(float value, const AxisFrame& frame, bool upper) {
    const double step = std::ldexp(1.0, int(frame.exponent) - 142);
    const double q = (double(value) - double(planeOf(frame.base, frame.exponent, 0))) / step;
    int32_t n = int32_t(std::clamp(upper ? std::ceil(q) : std::floor(q), 0.0, 255.0));
    // The sum in planeOf rounds: move outwards until the box contains the value.
    if (upper)
        while (n < 255 && planeOf(frame.base, frame.exponent, uint32_t(n)) < value) ++n;
    else
        while (n > 0 && planeOf(frame.base, frame.exponent, uint32_t(n)) > value) --n;
    return uint32_t(n);
}

class Collapser {
public:
    Collapser(const std::vector<gpu::BvhNode>& nodes, WideCollapse rule) : m_nodes(nodes), m_rule(rule) {
        if (m_rule == WideCollapse::Optimal) optimise();
    }

    std::vector<gpu::WideNode> run() {
        m_wide.reserve(m_nodes.size() / 2 + 1);
        m_wide.emplace_back();
        const gpu::BvhNode& root = m_nodes[0];
        if (root.primCount > 0) {
            fillNode(0, {0u});  // the whole scene is one leaf
        } else if (m_nodes.size() > 1) {
            fill(0, 0);
        }  // else no primitives: the default node, without children
        return std::move(m_wide);
    }

    // The total surface area of the binary nodes that became wide nodes (after run()).
    double wideArea() const { return m_area; }

private:
    bool isInterior(uint32_t index) const { return m_nodes[index].primCount == 0; }
    // A binary interior node's children: the next node, and the one its offset names.
    uint32_t left(uint32_t n) const { return n + 1; }
    uint32_t right(uint32_t n) const { return m_nodes[n].offset; }

    // The dynamic programme (see the top of this file): m_cover[n][k - 1] = D(n, k),
    // m_asNode[n] = W(n). Children follow their parent in the depth-first array, so one pass
    // from the back sees both children before their parent.
    void optimise() {
        m_cover.assign(m_nodes.size(), {});
        m_asNode.assign(m_nodes.size(), 0.0);
        for (size_t i = m_nodes.size(); i-- > 0;) {
            const auto n = uint32_t(i);
            if (!isInterior(n)) continue;
            m_asNode[n] = double(nodeArea(m_nodes[n])) + splitCost(n, WIDE_NODE_ARITY, bestSplit(n, WIDE_NODE_ARITY));
            for (uint32_t k = 1; k <= WIDE_NODE_ARITY; ++k)
                m_cover[n][k - 1] = k == 1 ? m_asNode[n] : std::min(m_asNode[n], splitCost(n, k, bestSplit(n, k)));
        }
    }
    // D(l, j) + D(r, k - j): n's k slots shared j to its left child and k - j to its right.
    double splitCost(uint32_t n, uint32_t k, uint32_t j) const {
        return m_cover[left(n)][j - 1] + m_cover[right(n)][k - j - 1];
    }
    // The j in [1, k - 1] of least splitCost (k >= 2), the first of equals.
    uint32_t bestSplit(uint32_t n, uint32_t k) const {
        uint32_t best = 1;
        for (uint32_t j = 2; j < k; ++j)
            if (splitCost(n, k, j) < splitCost(n, k, best)) best = j;
        return best;
    }
    // Appends the at most k nodes that cover n's subtree at least cost: n itself (a leaf, or
    // a wide node of its own), or its children's covers.
    void cover(uint32_t n, uint32_t k, std::vector<uint32_t>& out) const {
        if (!isInterior(n) || k == 1 || m_cover[n][k - 1] >= m_asNode[n]) {
            out.push_back(n);
            return;
        }
        const uint32_t j = bestSplit(n, k);
        cover(left(n), j, out);
        cover(right(n), k - j, out);
    }

    // Makes m_wide[slot] the node for binary interior node n, with the children the rule
    // picks, then builds the interior children's nodes.
    void fill(uint32_t slot, uint32_t n) {
        m_area += double(nodeArea(m_nodes[n]));
        std::vector<uint32_t> children;
        if (m_rule == WideCollapse::Optimal) {
            const uint32_t j = bestSplit(n, WIDE_NODE_ARITY);
            cover(left(n), j, children);
            cover(right(n), WIDE_NODE_ARITY - j, children);
        } else {
            children = {left(n), right(n)};
            openWidest(children);
        }
        fillNode(slot, children);
    }

    // The greedy rule: opens the interior child of largest area until there are four (or
    // only leaves).
    void openWidest(std::vector<uint32_t>& children) const {
        while (children.size() < WIDE_NODE_ARITY) {
            int widest = -1;
            float widestArea = -1.0f;
            for (size_t i = 0; i < children.size(); ++i)
                if (isInterior(children[i]) && nodeArea(m_nodes[children[i]]) > widestArea) {
                    widest = int(i);
                    widestArea = nodeArea(m_nodes[children[i]]);
                }
            if (widest < 0) break;
            uint32_t opened = children[size_t(widest)];
            children[size_t(widest)] = left(opened);
            children.push_back(right(opened));
        }
    }

    // Makes m_wide[slot] the quantized node over the binary nodes `children`.
    void fillNode(uint32_t slot, const std::vector<uint32_t>& children) {
        glm::vec3 lo(FLT_MAX), hi(-FLT_MAX);
        for (uint32_t c : children) {
            lo = glm::min(lo, m_nodes[c].boundsMin);
            hi = glm::max(hi, m_nodes[c].boundsMax);
        }
        gpu::WideNode node{};
        AxisFrame frame[3];
        for (int axis = 0; axis < 3; ++axis) {
            frame[axis] = frameFor(lo[axis], hi[axis]);
            node.base[axis] = frame[axis].base;
        }
        node.meta = frame[0].exponent | frame[1].exponent << 8 | frame[2].exponent << 16;
        uint32_t* loPlanes[3] = {&node.loX, &node.loY, &node.loZ};
        uint32_t* hiPlanes[3] = {&node.hiX, &node.hiY, &node.hiZ};
        uint32_t* refs[WIDE_NODE_ARITY] = {&node.child0, &node.child1, &node.child2, &node.child3};
        std::vector<std::pair<uint32_t, uint32_t>> interior;  // (wide slot, binary node)
        for (size_t c = 0; c < children.size(); ++c) {
            const gpu::BvhNode& child = m_nodes[children[c]];
            node.meta |= 1u << (gpu::WIDE_CHILD_MASK_SHIFT + c);
            for (int axis = 0; axis < 3; ++axis) {
                *loPlanes[axis] |= quantize(child.boundsMin[axis], frame[axis], false) << (8 * c);
                *hiPlanes[axis] |= quantize(child.boundsMax[axis], frame[axis], true) << (8 * c);
            }
            if (child.primCount > 0) {
                *refs[c] = child.offset | child.primCount << BVH_COUNT_SHIFT;
            } else {
                uint32_t childSlot = uint32_t(m_wide.size());
                m_wide.emplace_back();
                *refs[c] = childSlot;
                interior.push_back({childSlot, children[c]});
            }
        }
        m_wide[slot] = node;
        // Depth first: each child's subtree follows its siblings' nodes.
        for (auto [childSlot, binary] : interior) fill(childSlot, binary);
    }

    const std::vector<gpu::BvhNode>& m_nodes;
    const WideCollapse m_rule;
    std::vector<gpu::WideNode> m_wide;
    std::vector<std::array<double, WIDE_NODE_ARITY>> m_cover;  // the optimal rule's D(n, k)
    std::vector<double> m_asNode;                              // and its W(n)
    double m_area = 0.0;
};

}  // namespace

std::vector<gpu::WideNode> makeWideNodes(const std::vector<gpu::BvhNode>& nodes, WideCollapse rule) {
    if (nodes.empty()) return {};
    return Collapser(nodes, rule).run();
}

double wideNodeArea(const std::vector<gpu::BvhNode>& nodes, WideCollapse rule) {
    if (nodes.empty()) return 0.0;
    Collapser collapser(nodes, rule);
    collapser.run();
    return collapser.wideArea();
}

uint32_t wideStackDepth(const std::vector<gpu::WideNode>& nodes) {
    // Interior children follow their parent (Collapser::fill), so one pass in order sees
    // every node's depth before its children's.
    std::vector<uint32_t> depth(nodes.size(), 0);
    uint32_t deepest = 1;
    if (!nodes.empty()) depth[0] = 1;
    for (size_t i = 0; i < nodes.size(); ++i) {
        if (depth[i] == 0) continue;  // not reached from the root
        deepest = std::max(deepest, depth[i]);
        for (uint32_t c = 0; c < WIDE_NODE_ARITY; ++c) {
            const WideChildBox child = decodeWideChild(nodes[i], c);
            if (!child.exists || (child.ref >> BVH_COUNT_SHIFT) != 0) continue;  // none, or a leaf
            if (child.ref <= i || child.ref >= nodes.size())
                throw std::logic_error("wideStackDepth: node " + std::to_string(i) + " refers to node " +
                                       std::to_string(child.ref));
            depth[child.ref] = depth[i] + 1;
        }
    }
    return deepest;
}

uint32_t childStackDepth(const std::vector<gpu::WideNode>& nodes) {
    return (WIDE_NODE_ARITY - 1) * wideStackDepth(nodes);
}

WideChildBox decodeWideChild(const gpu::WideNode& node, uint32_t child) {
    const uint32_t loPlanes[3] = {node.loX, node.loY, node.loZ};
    const uint32_t hiPlanes[3] = {node.hiX, node.hiY, node.hiZ};
    WideChildBox box;
    for (int axis = 0; axis < 3; ++axis) {
        const uint32_t exponent = (node.meta >> (8 * axis)) & 0xffu;
        box.lo[axis] = planeOf(node.base[axis], exponent, (loPlanes[axis] >> (8 * child)) & 0xffu);
        box.hi[axis] = planeOf(node.base[axis], exponent, (hiPlanes[axis] >> (8 * child)) & 0xffu);
    }
    const uint32_t refs[WIDE_NODE_ARITY] = {node.child0, node.child1, node.child2, node.child3};
    box.ref = refs[child];
    box.exists = ((node.meta >> (gpu::WIDE_CHILD_MASK_SHIFT + child)) & 1u) != 0;
    return box;
}

}  // namespace penumbra
