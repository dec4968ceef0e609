// The light BVH: build (pbrt-v4 BVHLightSampler::buildBVH and EvaluateCost), flattening,
// importance (CompactLightBounds::Importance), descent and pmf replay. See light_bvh.h.
#include "render/light_bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace penumbra {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

float safeSqrt(float x) { return std::sqrt(std::max(x, 0.0f)); }
float safeAcos(float x) { return std::acos(std::clamp(x, -1.0f, 1.0f)); }

// Rotation of v about unit axis k by angle theta (Rodrigues' formula).
glm::vec3 rotate(glm::vec3 v, glm::vec3 k, float theta) {
    float c = std::cos(theta), s = std::sin(theta);
    return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1.0f - c);
}

// The smallest cone holding cones (a, cosA) and (b, cosB) (pbrt-v4 Union(DirectionCone,
// DirectionCone), vecmath.cpp; PBR book 4th ed. section 3.8.4).
void coneUnion(glm::vec3& a, float& cosA, glm::vec3 b, float cosB) {
    float thetaA = safeAcos(cosA), thetaB = safeAcos(cosB);
    float thetaD = safeAcos(glm::dot(a, b));
    if (std::min(thetaD + thetaB, kPi) <= thetaA) return;
    if (std::min(thetaD + thetaA, kPi) <= thetaB) {
        a = b;
        cosA = cosB;
        return;
    }
    float thetaO = (thetaA + thetaD + thetaB) / 2.0f;
    glm::vec3 k = glm::cross(a, b);
    if (thetaO >= kPi || glm::dot(k, k) == 0.0f) {
        cosA = -1.0f;  // the whole sphere
        return;
    }
    a = glm::normalize(rotate(a, glm::normalize(k), thetaO - thetaA));
    cosA = std::cos(thetaO);
}

// A union of LightBounds while building; `any` false is the empty set.
struct Accum {
    bool any = false;
    glm::vec3 lo{0.0f}, hi{0.0f};
    float power = 0.0f;
    glm::vec3 axis{0.0f, 0.0f, 1.0f};
    float cosThetaO = 1.0f, cosThetaE = 1.0f;
    bool twoSided = false;

    void add(const LightBounds& l) {
        add(l.boundsMin, l.boundsMax, l.power, l.axis, l.cosThetaO, l.cosThetaE, l.twoSided);
    }
    void add(const Accum& o) {
        if (o.any) add(o.lo, o.hi, o.power, o.axis, o.cosThetaO, o.cosThetaE, o.twoSided);
    }
    void add(glm::vec3 l, glm::vec3 h, float p, glm::vec3 w, float cosO, float cosE, bool two) {
        if (!any) {
            *this = Accum{true, l, h, p, w, cosO, cosE, two};
            return;
        }
        lo = glm::min(lo, l);
        hi = glm::max(hi, h);
        power += p;
        coneUnion(axis, cosThetaO, w, cosO);
        cosThetaE = std::min(cosThetaE, cosE);
        twoSided = twoSided || two;
    }
};

float surfaceArea(glm::vec3 d) { return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x); }

// pbrt-v4 BVHLightSampler::EvaluateCost: power x the solid-angle measure of the cone the
// lights emit into (M_Omega, Conty Estevez and Kulla 2018 eq. 1) x the box's surface area,
// with Kr penalizing thin boxes split along their short axis.
float splitCost(const Accum& b, glm::vec3 nodeDiagonal, int dim) {
    float thetaO = safeAcos(b.cosThetaO), thetaE = safeAcos(b.cosThetaE);
    float thetaW = std::min(thetaO + thetaE, kPi);
    float sinThetaO = safeSqrt(1.0f - b.cosThetaO * b.cosThetaO);
    float mOmega =
        2.0f * kPi * (1.0f - b.cosThetaO) +
        kPi / 2.0f *
            (2.0f * thetaW * sinThetaO - std::cos(thetaO - 2.0f * thetaW) - 2.0f * thetaO * sinThetaO + b.cosThetaO);
    float kr = std::max({nodeDiagonal.x, nodeDiagonal.y, nodeDiagonal.z}) / nodeDiagonal[dim];
    return b.power * mOmega * kr * surfaceArea(b.hi - b.lo);
}

// Rounded down, so that the decoded cone only widens (pbrt-v4 QuantizeCos).
uint32_t quantizeCos(float c) { return uint32_t(std::floor(std::clamp((c + 1.0f) / 2.0f, 0.0f, 1.0f) * 65535.0f)); }
float decodeCos(uint32_t q) { return float(q) / 65535.0f * 2.0f - 1.0f; }

gpu::LightBvhNode makeNode(const Accum& a, uint32_t childOrItem) {
    gpu::LightBvhNode node{};
    node.boundsMin = a.lo;
    node.boundsMax = a.hi;
    node.power = a.power;
    node.axis = a.axis;
    node.cosines = quantizeCos(a.cosThetaO) | (quantizeCos(a.cosThetaE) << 16);
    node.childOrItem = childOrItem | (a.twoSided ? gpu::LIGHT_BVH_TWO_SIDED : 0u);
    return node;
}

// Past this depth, splits are by count: the trail's 64 bits then always suffice.
constexpr int kSahDepth = 32;
constexpr int kBuckets = 12;

struct Builder {
    std::vector<LightBounds>& lights;
    LightBvh& out;

    uint32_t build(size_t start, size_t end, uint64_t trail, int depth) {
        if (end - start == 1) {
            const LightBounds& l = lights[start];
            uint32_t item = uint32_t(out.items.size());
            out.items.push_back({l.light, l.primitive, uint32_t(trail), uint32_t(trail >> 32)});
            Accum a;
            a.add(l);
            out.nodes.push_back(makeNode(a, gpu::LIGHT_BVH_LEAF | item));
            return uint32_t(out.nodes.size() - 1);
        }
        Accum all;
        glm::vec3 cLo(std::numeric_limits<float>::max()), cHi(-std::numeric_limits<float>::max());
        for (size_t i = start; i < end; ++i) {
            all.add(lights[i]);
            glm::vec3 c = (lights[i].boundsMin + lights[i].boundsMax) * 0.5f;
            cLo = glm::min(cLo, c);
            cHi = glm::max(cHi, c);
        }
        size_t mid = (start + end) / 2;
        if (depth < kSahDepth) mid = sahSplit(start, end, all, cLo, cHi);
        if (mid == start || mid == end) mid = (start + end) / 2;

        uint32_t index = uint32_t(out.nodes.size());
        out.nodes.push_back(makeNode(all, 0));
        build(start, mid, trail, depth + 1);  // the first child is the next node
        uint32_t second = build(mid, end, trail | (uint64_t(1) << depth), depth + 1);
        if (second > gpu::LIGHT_BVH_INDEX_MASK) throw std::runtime_error("light BVH: too many lights");
        out.nodes[index].childOrItem |= second;
        return index;
    }

    // pbrt-v4's bucketed split: the bucket boundary of least cost over the three axes.
    size_t sahSplit(size_t start, size_t end, const Accum& all, glm::vec3 cLo, glm::vec3 cHi) {
        glm::vec3 diagonal = all.hi - all.lo;
        float best = std::numeric_limits<float>::infinity();
        int bestDim = -1, bestBucket = -1;
        auto bucketOf = [&](const LightBounds& l, int dim) {
            float c = (l.boundsMin[dim] + l.boundsMax[dim]) * 0.5f;
            int b = int(kBuckets * ((c - cLo[dim]) / (cHi[dim] - cLo[dim])));
            return std::clamp(b, 0, kBuckets - 1);
        };
        for (int dim = 0; dim < 3; ++dim) {
            if (!(cHi[dim] > cLo[dim])) continue;
            std::array<Accum, kBuckets> buckets;
            for (size_t i = start; i < end; ++i) buckets[bucketOf(lights[i], dim)].add(lights[i]);
            std::array<Accum, kBuckets> above;  // above[i]: buckets i.. together
            above[kBuckets - 1] = buckets[kBuckets - 1];
            for (int i = kBuckets - 2; i >= 0; --i) {
                above[i] = buckets[i];
                above[i].add(above[i + 1]);
            }
            Accum below;
            for (int i = 0; i < kBuckets - 1; ++i) {
                below.add(buckets[i]);
                if (!below.any || !above[i + 1].any) continue;
                float cost = splitCost(below, diagonal, dim) + splitCost(above[i + 1], diagonal, dim);
                if (cost > 0.0f && cost < best) {
                    best = cost;
                    bestDim = dim;
                    bestBucket = i;
                }
            }
        }
        if (bestDim < 0) return (start + end) / 2;
        auto it = std::partition(lights.begin() + start, lights.begin() + end,
                                 [&](const LightBounds& l) { return bucketOf(l, bestDim) <= bestBucket; });
        return size_t(it - lights.begin());
    }
};

// cos(max(0, a - b)) and sin(max(0, a - b)) from the sines and cosines of a and b.
float cosSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 1.0f : cosA * cosB + sinA * sinB;
}
float sinSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 0.0f : sinA * cosB - cosA * sinB;
}

// The weights of an interior node's two children at (p, n): their importances, or, where
// both bounds are zero (the parent's looser bound was not), their powers. Unlike pbrt-v4,
// which then declines to sample, every item keeps a probability and the pmfs over all items
// sum to exactly 1; a light chosen where its bound is zero contributes nothing, so this
// costs a wasted sample, never bias.
void childWeights(const LightBvh& bvh, uint32_t index, uint32_t second, glm::vec3 p, glm::vec3 n, float& c0,
                  float& c1) {
    c0 = lightBvhImportance(bvh.nodes[index + 1], p, n);
    c1 = lightBvhImportance(bvh.nodes[second], p, n);
    if (!(c0 + c1 > 0.0f)) {
        c0 = bvh.nodes[index + 1].power;
        c1 = bvh.nodes[second].power;
    }
}

}  // namespace

LightBounds pointLightBounds(glm::vec3 position, float meanIntensity, uint32_t light) {
    // Emits everywhere: cone of normals the whole sphere, theta_e = pi/2 (pbrt-v4 PointLight::Bounds).
    return {position, position, 4.0f * kPi * meanIntensity, {0.0f, 0.0f, 1.0f}, -1.0f, 0.0f, false, light, ~0u};
}

LightBounds spotLightBounds(glm::vec3 position, glm::vec3 axis, float cosInner, float cosOuter, float meanIntensity,
                            uint32_t light) {
    // pbrt-v4 SpotLight::Bounds: the full cone is theta_o = the inner angle plus theta_e
    // = the falloff's width; its power is bounded by that of a point light.
    float cosThetaE = std::cos(safeAcos(cosOuter) - safeAcos(cosInner));
    return {position, position, 4.0f * kPi * meanIntensity, glm::normalize(axis), cosInner, cosThetaE, false,
            light,    ~0u};
}

LightBounds sphereLightBounds(glm::vec3 center, float radius, float meanRadiance, uint32_t light) {
    float area = 4.0f * kPi * radius * radius;
    return {center - radius,
            center + radius,
            kPi * area * meanRadiance,
            {0.0f, 0.0f, 1.0f},
            -1.0f,
            0.0f,
            false,
            light,
            ~0u};
}

LightBounds flatLightBounds(glm::vec3 boundsMin, glm::vec3 boundsMax, glm::vec3 normal, float area, float meanRadiance,
                            bool twoSided, uint32_t light, uint32_t primitive) {
    float power = kPi * area * meanRadiance * (twoSided ? 2.0f : 1.0f);
    return {boundsMin, boundsMax, power, glm::normalize(normal), 1.0f, 0.0f, twoSided, light, primitive};
}

LightBvh buildLightBvh(std::vector<LightBounds> lights, uint32_t infiniteCount) {
    LightBvh out;
    out.infiniteCount = infiniteCount;
    std::erase_if(lights, [](const LightBounds& l) { return !(l.power > 0.0f) || !std::isfinite(l.power); });
    if (lights.empty()) return out;
    out.nodes.reserve(2 * lights.size() - 1);
    out.items.reserve(lights.size());
    Builder{lights, out}.build(0, lights.size(), 0, 0);
    return out;
}

gpu::LightImportanceTerms lightBvhImportanceTerms(const gpu::LightBvhNode& node) {
    const float cosThetaO = decodeCos(node.cosines & 0xffffu);
    const float halfDiagonal = 0.5f * glm::length(node.boundsMax - node.boundsMin);
    return {(node.boundsMin + node.boundsMax) * 0.5f,
            halfDiagonal * halfDiagonal,
            node.axis,
            node.power,
            cosThetaO,
            safeSqrt(1.0f - cosThetaO * cosThetaO),
            decodeCos(node.cosines >> 16),
            (node.childOrItem & gpu::LIGHT_BVH_TWO_SIDED) ? 1u : 0u};
}

float lightImportance(const gpu::LightImportanceTerms& t, glm::vec3 p, glm::vec3 n) {
    const glm::vec3 toP = p - t.center;
    const float d2Raw = glm::dot(toP, toP);
    // Inside the box's bounding sphere every direction may reach a light: no angular bound.
    if (d2Raw <= t.halfDiagonal2) return t.power / std::max(t.halfDiagonal2, 1e-20f);
    // Distance clamped to the box's size so that a point near a large box does not get an
    // unbounded importance (pbrt-v4 clamps with the half diagonal as well).
    const float d2 = std::max(d2Raw, t.halfDiagonal2);
    const glm::vec3 wi = toP / std::sqrt(d2Raw);
    // The cone of directions from p that the box subtends (pbrt-v4 BoundSubtendedDirections).
    const float cosThetaB = safeSqrt(1.0f - t.halfDiagonal2 / d2Raw);
    const float sinThetaB = safeSqrt(1.0f - cosThetaB * cosThetaB);
    // The smallest angle between a normal in the cone and a direction toward p from the box.
    // With normals in every direction (cos theta_o = -1: points, spheres) theta_x = 0 and
    // theta' = 0; the general form gives exactly 1 there too (sin theta_o = 0, and
    // cosSubClamped returns 1 or cos theta_w * -1 with cos theta_w = -1), so the shortcut
    // changes no value, and a kernel whose cone is a constant drops the general form.
    float cosThetaP = 1.0f;
    if (t.cosThetaO > -1.0f) {
        float cosThetaW = glm::dot(t.axis, wi);
        if (t.twoSided) cosThetaW = std::abs(cosThetaW);
        const float sinThetaW = safeSqrt(1.0f - cosThetaW * cosThetaW);
        const float cosThetaX = cosSubClamped(sinThetaW, cosThetaW, t.sinThetaO, t.cosThetaO);
        const float sinThetaX = sinSubClamped(sinThetaW, cosThetaW, t.sinThetaO, t.cosThetaO);
        cosThetaP = cosSubClamped(sinThetaX, cosThetaX, sinThetaB, cosThetaB);
    }
    if (cosThetaP <= t.cosThetaE) return 0.0f;
    float importance = t.power * cosThetaP / d2;
    if (n != glm::vec3(0.0f)) {
        // The shading normal's hemisphere: the smallest angle between n and a direction to the box.
        const float cosThetaI = std::abs(glm::dot(wi, n));
        const float sinThetaI = safeSqrt(1.0f - cosThetaI * cosThetaI);
        importance *= cosSubClamped(sinThetaI, cosThetaI, sinThetaB, cosThetaB);
    }
    return std::max(importance, 0.0f);
}

float lightBvhImportance(const gpu::LightBvhNode& node, glm::vec3 p, glm::vec3 n) {
    return lightImportance(lightBvhImportanceTerms(node), p, n);
}

float lightBvhTreeProbability(const LightBvh& bvh) {
    if (bvh.nodes.empty()) return 0.0f;
    return 1.0f / float(bvh.infiniteCount + 1);
}

LightBvhSample sampleLightBvh(const LightBvh& bvh, glm::vec3 p, glm::vec3 n, float u) {
    if (bvh.nodes.empty()) return {};
    uint32_t index = 0;
    float pmf = 1.0f;
    constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
    while (true) {
        const gpu::LightBvhNode& node = bvh.nodes[index];
        if (node.childOrItem & gpu::LIGHT_BVH_LEAF) {
            return {int32_t(node.childOrItem & gpu::LIGHT_BVH_INDEX_MASK), pmf};
        }
        const uint32_t second = node.childOrItem & gpu::LIGHT_BVH_INDEX_MASK;
        float c0, c1;
        childWeights(bvh, index, second, p, n, c0, c1);
        const float p0 = c0 / (c0 + c1);
        // The same expression as lightBvhPmf's, so that sampled and replayed pmfs agree exactly.
        if (u < p0) {
            pmf *= c0 / (c0 + c1);
            u = std::min(u / p0, kOneMinusEpsilon);
            index = index + 1;
        } else {
            pmf *= c1 / (c0 + c1);
            u = std::min((u - p0) / (1.0f - p0), kOneMinusEpsilon);
            index = second;
        }
    }
}

float lightBvhPmf(const LightBvh& bvh, glm::vec3 p, glm::vec3 n, uint32_t item) {
    if (bvh.nodes.empty() || item >= bvh.items.size()) return 0.0f;
    uint64_t trail = uint64_t(bvh.items[item].trailLow) | (uint64_t(bvh.items[item].trailHigh) << 32);
    uint32_t index = 0;
    float pmf = 1.0f;
    while (true) {
        const gpu::LightBvhNode& node = bvh.nodes[index];
        if (node.childOrItem & gpu::LIGHT_BVH_LEAF) return pmf;
        const uint32_t second = node.childOrItem & gpu::LIGHT_BVH_INDEX_MASK;
        float c0, c1;
        childWeights(bvh, index, second, p, n, c0, c1);
        pmf *= ((trail & 1u) ? c1 : c0) / (c0 + c1);
        index = (trail & 1u) ? second : index + 1;
        trail >>= 1;
    }
}

}  // namespace penumbra
