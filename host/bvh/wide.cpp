// The binary tree of build.cpp collapsed into the four-wide, quantized nodes the traversal
// reads (gpu::WideNode in shared/types.h; shaders/geometry/bvh.glsl, traverse.cpp).
//
// Collapsing: each wide node starts from a binary interior node's two children and, while it
// has fewer than four, opens the interior child of largest surface area into its two
// children (the greedy collapse of Wald et al. 2008, "Getting Rid of Packets", and of
// Embree's BVH4 builder: the large boxes are the ones most rays test). Every wide child is at
// least one binary level below its parent, so the wide tree is no deeper than the binary one
// (at most BVH_MAX_DEPTH), which bounds the traversal stack.
//
// Quantizing: Ylitie, Karras & Laine 2017, section 3.1, with one exponent per axis and node.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <string>

#include "bvh/bvh.h"

namespace penumbra {

namespace {

float stepOf(uint32_t biasedExponent) { return std::ldexp(1.0f, int(biasedExponent) - 127); }

// The smallest biased exponent e (1 to 254) whose step 2^(e - 127) reaches from `origin` past
// `top` in 255 steps, computed as the shader computes it (origin + 255 * step, rounded), so
// that q_hi = 255 always covers the top.
uint32_t exponentFor(float origin, float top) {
    uint32_t e = 1;
    double extent = double(top) - double(origin);
    if (extent > 0.0) {
        int exponent;
        std::frexp(extent / 255.0, &exponent);  // extent / 255 < 2^exponent
        e = uint32_t(std::clamp(exponent - 1 + 127, 1, 254));
    }
    while (e < 254 && !(origin + 255.0f * stepOf(e) >= top)) ++e;
    return e;
}

// One plane of one child: q with origin + q * step <= value (lower planes) or >= value
// (upper planes), as tight as the byte allows.
uint32_t quantize(float value, float origin, float step, bool upper) {
    double q = (double(value) - double(origin)) / double(step);
    int32_t n = int32_t(std::clamp(upper ? std::ceil(q) : std::floor(q), 0.0, 255.0));
    // Rounding in origin + n * step (the division above is exact, the sum is not) can land
    // on the wrong side of the value: move outwards until the box contains it.
    if (upper)
        while (n < 255 && origin + float(n) * step < value) ++n;
    else
        while (n > 0 && origin + float(n) * step > value) --n;
    return uint32_t(n);
}

class Collapser {
public:
    explicit Collapser(const std::vector<gpu::BvhNode>& nodes) : m_nodes(nodes) {}

    std::vector<gpu::WideNode> run() {
        m_wide.reserve(m_nodes.size() / 2 + 1);
        m_wide.emplace_back();
        const gpu::BvhNode& root = m_nodes[0];
        if (root.primCount > 0) {
            fill(0, {0u});  // the whole scene is one leaf
        } else if (m_nodes.size() > 1) {
            fill(0, {1u, root.offset});
        }  // else no primitives: the default node, without children
        return std::move(m_wide);
    }

private:
    bool isInterior(uint32_t index) const { return m_nodes[index].primCount == 0; }

    // Makes m_wide[slot] the node over the binary nodes `children`, opening interior ones
    // until there are four (or only leaves), then builds the interior children's nodes.
    void fill(uint32_t slot, std::vector<uint32_t> children) {
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
            children[size_t(widest)] = opened + 1;       // left child: the next node
            children.push_back(m_nodes[opened].offset);  // right child
        }

        glm::vec3 lo(FLT_MAX), hi(-FLT_MAX);
        for (uint32_t c : children) {
            lo = glm::min(lo, m_nodes[c].boundsMin);
            hi = glm::max(hi, m_nodes[c].boundsMax);
        }
        gpu::WideNode node{};
        node.origin = lo;
        uint32_t e[3];
        float step[3];
        for (int axis = 0; axis < 3; ++axis) {
            e[axis] = exponentFor(lo[axis], hi[axis]);
            step[axis] = stepOf(e[axis]);
        }
        node.meta = e[0] | e[1] << 8 | e[2] << 16;
        uint32_t* loPlanes[3] = {&node.loX, &node.loY, &node.loZ};
        uint32_t* hiPlanes[3] = {&node.hiX, &node.hiY, &node.hiZ};
        uint32_t* refs[WIDE_NODE_ARITY] = {&node.child0, &node.child1, &node.child2, &node.child3};
        std::vector<std::pair<uint32_t, uint32_t>> interior;  // (wide slot, binary node)
        for (size_t c = 0; c < children.size(); ++c) {
            const gpu::BvhNode& child = m_nodes[children[c]];
            node.meta |= 1u << (gpu::WIDE_CHILD_MASK_SHIFT + c);
            for (int axis = 0; axis < 3; ++axis) {
                *loPlanes[axis] |= quantize(child.boundsMin[axis], lo[axis], step[axis], false) << (8 * c);
                *hiPlanes[axis] |= quantize(child.boundsMax[axis], lo[axis], step[axis], true) << (8 * c);
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
        for (auto [childSlot, binary] : interior) fill(childSlot, {binary + 1, m_nodes[binary].offset});
    }

    const std::vector<gpu::BvhNode>& m_nodes;
    std::vector<gpu::WideNode> m_wide;
};

}  // namespace

std::vector<gpu::WideNode> makeWideNodes(const std::vector<gpu::BvhNode>& nodes) {
    if (nodes.empty()) return {};
    return Collapser(nodes).run();
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

WideChildBox decodeWideChild(const gpu::WideNode& node, uint32_t child) {
    const uint32_t loPlanes[3] = {node.loX, node.loY, node.loZ};
    const uint32_t hiPlanes[3] = {node.hiX, node.hiY, node.hiZ};
    WideChildBox box;
    for (int axis = 0; axis < 3; ++axis) {
        float step = stepOf((node.meta >> (8 * axis)) & 0xffu);
        box.lo[axis] = node.origin[axis] + float((loPlanes[axis] >> (8 * child)) & 0xffu) * step;
        box.hi[axis] = node.origin[axis] + float((hiPlanes[axis] >> (8 * child)) & 0xffu) * step;
    }
    const uint32_t refs[WIDE_NODE_ARITY] = {node.child0, node.child1, node.child2, node.child3};
    box.ref = refs[child];
    box.exists = ((node.meta >> (gpu::WIDE_CHILD_MASK_SHIFT + child)) & 1u) != 0;
    return box;
}

}  // namespace penumbra
