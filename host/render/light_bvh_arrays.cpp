// Light selection "bvh" -> GPU arrays (see light_bvh_arrays.h).
#include "render/light_bvh_arrays.h"

#include <bit>
#include <cmath>
#include <cstring>

#include "render/alias_table.h"
#include "render/scene_arrays.h"

namespace penumbra {
namespace {

float meanOf(glm::vec3 c) { return (c.x + c.y + c.z) / 3.0f; }

// Inverse of light_arrays.cpp's octahedralEncode (Cigolle et al. 2014, listing 2), as
// shaders/lights/spot.glsl decodes a spot light's axis.
glm::vec3 octahedralDecode(glm::vec2 e) {
    glm::vec3 v(e.x, e.y, 1.0f - std::fabs(e.x) - std::fabs(e.y));
    if (v.z < 0.0f) {
        glm::vec2 folded = (1.0f - glm::abs(glm::vec2(v.y, v.x))) *
                           glm::vec2(v.x >= 0.0f ? 1.0f : -1.0f, v.y >= 0.0f ? 1.0f : -1.0f);
        v.x = folded.x;
        v.y = folded.y;
    }
    return glm::normalize(v);
}

// A flat primitive's bounds: a quad (p0 origin, p1 and p2 its edges) or a triangle, with
// the front normal of shaders/lights/polygon_fallback.glsl, primitiveFrontNormal.
LightBounds flatPrimitiveBounds(const gpu::Primitive& p, const gpu::Light& light, uint32_t index, uint32_t primitive) {
    const bool twoSided = (light.flags & gpu::LIGHT_TWO_SIDED) != 0;
    const float radiance = meanOf(light.emission);
    if ((p.typeAndNormals & gpu::PRIM_TYPE_MASK) == gpu::PRIM_QUAD) {
        glm::vec3 lo = glm::min(glm::min(p.p0, p.p0 + p.p1), glm::min(p.p0 + p.p2, p.p0 + p.p1 + p.p2));
        glm::vec3 hi = glm::max(glm::max(p.p0, p.p0 + p.p1), glm::max(p.p0 + p.p2, p.p0 + p.p1 + p.p2));
        glm::vec3 n = glm::cross(p.p1, p.p2);
        return flatLightBounds(lo, hi, n, light.area, radiance, twoSided, index, primitive);
    }
    glm::vec3 n = glm::cross(p.p1 - p.p0, p.p2 - p.p0);
    const float area = 0.5f * glm::length(n);
    if (!(area > 0.0f)) n = glm::vec3(0.0f, 0.0f, 1.0f);  // power 0: dropped
    return flatLightBounds(glm::min(glm::min(p.p0, p.p1), p.p2), glm::max(glm::max(p.p0, p.p1), p.p2), n, area,
                           radiance, twoSided, index, primitive);
}

}  // namespace

std::vector<LightBounds> lightBoundsOf(const SceneArrays& arrays) {
    std::vector<LightBounds> bounds;
    for (uint32_t i = 0; i < arrays.lights.size(); ++i) {
        const gpu::Light& l = arrays.lights[i];
        switch (l.type) {
            case gpu::LIGHT_POINT: bounds.push_back(pointLightBounds(l.position, meanOf(l.emission), i)); break;
            case gpu::LIGHT_SPOT: {
                // makeSpotLight: the axis octahedral in first/count, cos outer in area, cos inner in flags.
                glm::vec3 axis = octahedralDecode({std::bit_cast<float>(l.first), std::bit_cast<float>(l.count)});
                bounds.push_back(
                    spotLightBounds(l.position, axis, std::bit_cast<float>(l.flags), l.area, meanOf(l.emission), i));
                break;
            }
            case gpu::LIGHT_SPHERE: {
                const float radius = std::sqrt(l.area / (4.0f * 3.14159265358979f));
                bounds.push_back(sphereLightBounds(l.position, radius, meanOf(l.emission), i));
                break;
            }
            case gpu::LIGHT_QUAD:
                // The whole quad is one item (~0u: sampled as the light it is).
                bounds.push_back(flatPrimitiveBounds(arrays.bvh.primitives[l.first], l, i, ~0u));
                break;
            case gpu::LIGHT_MESH:
                for (uint32_t k = 0; k < l.count; ++k) {
                    const uint32_t prim = arrays.meshTable[l.first + k].item;
                    bounds.push_back(flatPrimitiveBounds(arrays.bvh.primitives[prim], l, i, prim));
                }
                break;
            default: break;  // directional, environment: beside the tree
        }
    }
    return bounds;
}

std::vector<uint32_t> lightBvhHitPrimitives(const SceneArrays& arrays) {
    std::vector<uint32_t> hit;
    for (const gpu::LightBvhItem& item : arrays.lightBvh.tree.items) {
        const gpu::Light& light = arrays.lights[item.light];
        uint32_t prim = item.primitive;  // a mesh light's triangle
        if (prim == ~0u && (light.type == gpu::LIGHT_SPHERE || light.type == gpu::LIGHT_QUAD)) prim = light.first;
        hit.push_back(prim == ~0u ? gpu::NO_HIT : prim);
    }
    return hit;
}

void buildLightBvhArrays(SceneArrays& out) {
    LightBvhArrays& a = out.lightBvh;
    uint32_t infinite = 0;
    std::vector<uint32_t> tableItems;
    for (uint32_t i = 0; i < out.lights.size(); ++i) {
        const uint32_t type = out.lights[i].type;
        if (type == gpu::LIGHT_DIRECTIONAL || type == gpu::LIGHT_ENVIRONMENT) {
            tableItems.push_back(i);
            ++infinite;
        }
    }
    a.tree = buildLightBvh(lightBoundsOf(out), infinite);
    if (!a.tree.nodes.empty()) tableItems.push_back(gpu::NO_LIGHT);

    // One table entry each, equal weights (pbrt-v4: the tree counts as one infinite light).
    const std::vector<double> weights(tableItems.size(), 1.0);
    const auto table = buildAliasTable(weights, tableItems);
    a.tableOffset = uint32_t(out.lightTable.size());
    a.tableCount = uint32_t(table.size());
    out.lightTable.insert(out.lightTable.end(), table.begin(), table.end());

    static_assert(sizeof(gpu::LightBvhNode) == 3 * sizeof(glm::uvec4) &&
                  sizeof(gpu::LightBvhItem) == sizeof(glm::uvec4));
    const size_t primitives = out.bvh.primitives.size();
    a.itemsTexel = uint32_t(3 * a.tree.nodes.size());
    a.trailsTexel = uint32_t(a.itemsTexel + a.tree.items.size());
    a.texels.assign(a.trailsTexel + (primitives + 1) / 2, glm::uvec4(0u));
    if (a.tree.nodes.empty()) {
        a.texels.clear();
        return;
    }
    std::memcpy(a.texels.data(), a.tree.nodes.data(), a.tree.nodes.size() * sizeof(gpu::LightBvhNode));
    std::memcpy(a.texels.data() + a.itemsTexel, a.tree.items.data(), a.tree.items.size() * sizeof(gpu::LightBvhItem));
    const std::vector<uint32_t> hit = lightBvhHitPrimitives(out);
    for (size_t i = 0; i < a.tree.items.size(); ++i) {
        const gpu::LightBvhItem& item = a.tree.items[i];
        // Only lights a BRDF-sampled ray can hit need their trail found again.
        const uint32_t prim = hit[i];
        if (prim == gpu::NO_HIT) continue;
        glm::uvec4& texel = a.texels[a.trailsTexel + prim / 2];
        if (prim % 2 == 0) {
            texel.x = item.trailLow;
            texel.y = item.trailHigh;
        } else {
            texel.z = item.trailLow;
            texel.w = item.trailHigh;
        }
    }
}

}  // namespace penumbra
