// Lights -> GPU arrays (see light_arrays.h): gpu::Light records, mesh-light triangle tables
// and the light-selection alias tables.
#include "render/light_arrays.h"

#include <bit>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "render/alias_table.h"
#include "render/environment_map.h"
#include "render/scene_arrays.h"

namespace penumbra {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

gpu::Light makeLight(uint32_t type, glm::vec3 emission, glm::vec3 position = glm::vec3(0.0f)) {
    gpu::Light light{};
    light.type = type;
    light.emission = emission;
    light.position = position;
    return light;
}

// Octahedral coordinates of a unit vector (Cigolle et al. 2014, "A Survey of Efficient
// Representations for Independent Unit Vectors", JCGT 3(2), listing 1); spotAxis in
// shaders/lights/spot.glsl decodes them.
glm::vec2 octahedralEncode(glm::vec3 v) {
    glm::vec2 p = glm::vec2(v.x, v.y) / (std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z));
    if (v.z < 0.0f)
        p = (1.0f - glm::abs(glm::vec2(p.y, p.x))) * glm::vec2(p.x >= 0.0f ? 1.0f : -1.0f, p.y >= 0.0f ? 1.0f : -1.0f);
    return p;
}

gpu::Light makeSpotLight(const Light& l) {
    gpu::Light light = makeLight(gpu::LIGHT_SPOT, l.intensity, l.position);
    glm::vec2 axis = octahedralEncode(glm::normalize(l.direction));
    light.first = std::bit_cast<uint32_t>(axis.x);
    light.count = std::bit_cast<uint32_t>(axis.y);
    light.area = l.cosOuter;
    light.flags = std::bit_cast<uint32_t>(l.cosInner);
    return light;
}

// An environment with a map: its texels and sampling table go to out.environmentTexels and
// out.environmentTable; the light holds the map's size and its mean radiance over solid
// angle (position), L in the power 4 pi^2 R^2 L (pbrt-v4 ImageInfiniteLight::Phi sums its
// equal-area texels the same way).
gpu::Light makeEnvironmentMapLight(const Light& l, SceneArrays& out, EnvironmentTexels texels) {
    const EnvironmentImage& map = *l.map;
    gpu::Light light = makeLight(gpu::LIGHT_ENVIRONMENT, l.intensity);
    light.flags = gpu::LIGHT_ENVIRONMENT_MAP;
    light.first = map.width;
    light.count = map.height;
    glm::dvec3 sum(0.0);
    for (uint32_t row = 0; row < map.height; ++row) {
        double omega = environmentTexelSolidAngle(row, map.width, map.height);
        for (uint32_t col = 0; col < map.width; ++col)
            sum += glm::dvec3(map.texels[size_t(row) * map.width + col]) * omega;
    }
    light.position = glm::vec3(sum / (4.0 * std::numbers::pi));
    // A black map is sampled in proportion to solid angle; it emits nothing either way.
    out.environmentTable = buildEnvironmentTable(map);
    if (texels == EnvironmentTexels::InArrays) {
        out.environmentTexels.resize(map.texels.size());
        writeEnvironmentTexels(map, out.environmentTexels.data());
    }
    return light;
}

}  // namespace

bool isDeltaLight(uint32_t type) {
    return type == gpu::LIGHT_POINT || type == gpu::LIGHT_SPOT || type == gpu::LIGHT_DIRECTIONAL;
}

double lightPower(const gpu::Light& light, float sceneRadius) {
    double mean = (double(light.emission.x) + light.emission.y + light.emission.z) / 3.0;
    double pi = std::numbers::pi;
    double r2 = double(sceneRadius) * sceneRadius;
    switch (light.type) {
        case gpu::LIGHT_POINT: return 4.0 * pi * mean;
        case gpu::LIGHT_SPOT: return mean * spotFalloffIntegral(std::bit_cast<float>(light.flags), light.area);
        case gpu::LIGHT_DIRECTIONAL: return pi * r2 * mean;
        case gpu::LIGHT_ENVIRONMENT: {
            // A map's L is its mean radiance over solid angle (makeEnvironmentMapLight).
            if (light.flags & gpu::LIGHT_ENVIRONMENT_MAP)
                mean = (double(light.position.x) + light.position.y + light.position.z) / 3.0;
            return 4.0 * pi * pi * r2 * mean;
        }
        default: return pi * mean * light.area * ((light.flags & gpu::LIGHT_TWO_SIDED) ? 2.0 : 1.0);
    }
}

void appendLightsWithoutGeometry(const std::vector<Light>& lights, SceneArrays& out,
                                 EnvironmentTexels environmentTexels) {
    // Several constant environments add up to one: a ray escaping the scene sees their sum.
    // A map is the scene's only environment (the loaders allow one).
    glm::vec3 environment(0.0f);
    bool hasEnvironment = false;
    const Light* mapped = nullptr;
    for (const Light& l : lights) {
        switch (l.type) {
            case LightType::Point: out.lights.push_back(makeLight(gpu::LIGHT_POINT, l.intensity, l.position)); break;
            case LightType::Spot: out.lights.push_back(makeSpotLight(l)); break;
            case LightType::Directional:
                out.lights.push_back(makeLight(gpu::LIGHT_DIRECTIONAL, l.intensity, glm::normalize(l.direction)));
                break;
            case LightType::Environment:
                if (l.map) mapped = &l;
                if (hasEnvironment && mapped) throw std::logic_error("an environment map beside another environment");
                environment += l.intensity;
                hasEnvironment = true;
                break;
        }
    }
    if (hasEnvironment) {
        out.environmentLight = uint32_t(out.lights.size());
        out.lights.push_back(mapped ? makeEnvironmentMapLight(*mapped, out, environmentTexels)
                                    : makeLight(gpu::LIGHT_ENVIRONMENT, environment));
    }
}

gpu::Light makeSphereLight(const Shape& shape, uint32_t primitive) {
    gpu::Light light = makeLight(gpu::LIGHT_SPHERE, shape.emission, shape.center);
    light.first = primitive;
    light.area = 4.0f * kPi * shape.radius * shape.radius;
    return light;
}

gpu::Light makeQuadLight(const Shape& shape, uint32_t primitive) {
    gpu::Light light = makeLight(gpu::LIGHT_QUAD, shape.emission, shape.origin);
    light.first = primitive;
    light.flags = shape.twoSided ? gpu::LIGHT_TWO_SIDED : 0u;
    const float lengths = glm::length(shape.edgeU) * glm::length(shape.edgeV);
    if (std::abs(glm::dot(shape.edgeU, shape.edgeV)) <= 1e-5f * lengths) light.flags |= gpu::LIGHT_RECTANGLE;
    light.area = glm::length(glm::cross(shape.edgeU, shape.edgeV));
    return light;
}

gpu::Light makeMeshLight(const Shape& shape, double area) {
    gpu::Light light = makeLight(gpu::LIGHT_MESH, shape.emission);
    light.flags = shape.twoSided ? gpu::LIGHT_TWO_SIDED : 0u;
    light.area = float(area);
    return light;
}

void finishAreaLights(const std::vector<uint32_t>& leafIndex, std::vector<MeshLightTriangles>& meshLights,
                      SceneArrays& out) {
    for (gpu::Light& light : out.lights)
        if (light.type == gpu::LIGHT_SPHERE || light.type == gpu::LIGHT_QUAD) light.first = leafIndex[light.first];
    for (MeshLightTriangles& mesh : meshLights) {
        gpu::Light& light = out.lights[mesh.light];
        for (uint32_t& p : mesh.prims) p = leafIndex[p];
        auto table = buildAliasTable(mesh.areas, mesh.prims);
        light.first = uint32_t(out.meshTable.size());
        light.count = uint32_t(table.size());
        out.meshTable.insert(out.meshTable.end(), table.begin(), table.end());
    }
}

void buildLightSelection(LightSelection selection, SceneArrays& out) {
    std::vector<double> weights;
    std::vector<uint32_t> items;
    std::vector<double> deltaWeights, continuousWeights;
    std::vector<uint32_t> deltaItems, continuousItems;
    for (uint32_t i = 0; i < out.lights.size(); ++i) {
        double w = selection != LightSelection::Uniform ? lightPower(out.lights[i], out.boundsRadius) : 1.0;
        weights.push_back(w);
        items.push_back(i);
        bool delta = isDeltaLight(out.lights[i].type);
        (delta ? deltaWeights : continuousWeights).push_back(w);
        (delta ? deltaItems : continuousItems).push_back(i);
    }
    out.lightTable = buildAliasTable(weights, items);
    for (const gpu::AliasEntry& e : out.lightTable) out.lights[e.item].selectionProb = e.pmf;
    double deltaSum = 0.0, continuousSum = 0.0;
    for (uint32_t i : deltaItems) deltaSum += out.lights[i].selectionProb;
    for (uint32_t i : continuousItems) continuousSum += out.lights[i].selectionProb;
    // A sub-table whose lights all have zero selection probability would be built uniform:
    // leave it empty instead, so those lights are never sampled (they emit nothing).
    if (!(deltaSum > 0.0)) deltaItems.clear();
    if (!(continuousSum > 0.0)) continuousItems.clear();
    if (deltaItems.empty()) deltaWeights.clear();
    if (continuousItems.empty()) continuousWeights.clear();
    auto delta = buildAliasTable(deltaWeights, deltaItems);
    auto continuous = buildAliasTable(continuousWeights, continuousItems);
    out.deltaTableOffset = uint32_t(out.lightTable.size());
    out.deltaCount = uint32_t(delta.size());
    out.lightTable.insert(out.lightTable.end(), delta.begin(), delta.end());
    out.continuousTableOffset = uint32_t(out.lightTable.size());
    out.continuousCount = uint32_t(continuous.size());
    out.lightTable.insert(out.lightTable.end(), continuous.begin(), continuous.end());
    out.deltaScale = deltaItems.empty() ? 0.0f : float(1.0 / deltaSum);
    out.continuousScale = continuousItems.empty() ? 0.0f : float(1.0 / continuousSum);
}

}  // namespace penumbra
