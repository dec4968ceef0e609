// Scene -> GPU arrays: primitives, lights, materials and alias tables (see scene_arrays.h).
#include "render/scene_arrays.h"

#include <cmath>
#include <numbers>

#include "render/alias_table.h"
#include "render/material_arrays.h"

namespace penumbra {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

float triangleArea(glm::vec3 a, glm::vec3 b, glm::vec3 c) { return 0.5f * glm::length(glm::cross(b - a, c - a)); }

gpu::Primitive makePrimitive(uint32_t type, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, uint32_t material,
                             uint32_t light, uint32_t normalsPlusOne = 0) {
    gpu::Primitive prim{};
    prim.p0 = p0;
    prim.p1 = p1;
    prim.p2 = p2;
    prim.typeAndNormals = type | (normalsPlusOne << 2);
    prim.material = material;
    prim.light = light;
    return prim;
}

gpu::Light makeLight(uint32_t type, glm::vec3 emission, glm::vec3 position = glm::vec3(0.0f)) {
    gpu::Light light{};
    light.type = type;
    light.emission = emission;
    light.position = position;
    return light;
}

}  // namespace

double lightPower(const gpu::Light& light, float sceneRadius) {
    double mean = (double(light.emission.x) + light.emission.y + light.emission.z) / 3.0;
    double pi = std::numbers::pi;
    double r2 = double(sceneRadius) * sceneRadius;
    switch (light.type) {
        case gpu::LIGHT_POINT: return 4.0 * pi * mean;
        case gpu::LIGHT_DIRECTIONAL: return pi * r2 * mean;
        case gpu::LIGHT_ENVIRONMENT: return 4.0 * pi * pi * r2 * mean;
        default: return pi * mean * light.area * ((light.flags & gpu::LIGHT_TWO_SIDED) ? 2.0 : 1.0);
    }
}

SceneArrays buildSceneArrays(const Scene& scene, const BvhOptions& bvhOptions) {
    SceneArrays out;

    out.materials = packMaterials(scene.materials);

    // Lights without geometry first, then one light per emitting shape. Area lights record
    // their primitive's *input* index for now; it becomes the BVH leaf-order index below.
    // Several constant environments add up to one: a ray escaping the scene sees their sum.
    glm::vec3 environment(0.0f);
    bool hasEnvironment = false;
    for (const Light& l : scene.lights) {
        switch (l.type) {
            case LightType::Point: out.lights.push_back(makeLight(gpu::LIGHT_POINT, l.intensity, l.position)); break;
            case LightType::Directional:
                out.lights.push_back(makeLight(gpu::LIGHT_DIRECTIONAL, l.intensity, glm::normalize(l.direction)));
                break;
            case LightType::Environment:
                environment += l.intensity;
                hasEnvironment = true;
                break;
        }
    }
    if (hasEnvironment) {
        out.environmentLight = uint32_t(out.lights.size());
        out.lights.push_back(makeLight(gpu::LIGHT_ENVIRONMENT, environment));
    }

    std::vector<gpu::Primitive> prims;
    struct MeshLightTriangles {
        uint32_t light;
        std::vector<uint32_t> prims;
        std::vector<double> areas;
    };
    std::vector<MeshLightTriangles> meshLights;
    for (const Shape& shape : scene.shapes) {
        uint32_t lightIndex = shape.isEmitter() ? uint32_t(out.lights.size()) : gpu::NO_LIGHT;
        uint32_t flags = shape.twoSided ? gpu::LIGHT_TWO_SIDED : 0u;
        switch (shape.type) {
            case ShapeType::Sphere: {
                if (lightIndex != gpu::NO_LIGHT) {
                    gpu::Light light = makeLight(gpu::LIGHT_SPHERE, shape.emission, shape.center);
                    light.first = uint32_t(prims.size());
                    light.area = 4.0f * kPi * shape.radius * shape.radius;
                    out.lights.push_back(light);
                }
                prims.push_back(makePrimitive(gpu::PRIM_SPHERE, shape.center, glm::vec3(shape.radius, 0, 0),
                                              glm::vec3(0.0f), shape.material, lightIndex));
                break;
            }
            case ShapeType::Quad: {
                if (lightIndex != gpu::NO_LIGHT) {
                    gpu::Light light = makeLight(gpu::LIGHT_QUAD, shape.emission, shape.origin);
                    light.first = uint32_t(prims.size());
                    light.flags = flags;
                    light.area = glm::length(glm::cross(shape.edgeU, shape.edgeV));
                    out.lights.push_back(light);
                }
                prims.push_back(makePrimitive(gpu::PRIM_QUAD, shape.origin, shape.edgeU, shape.edgeV, shape.material,
                                              lightIndex));
                break;
            }
            case ShapeType::Mesh: {
                MeshLightTriangles mesh{lightIndex, {}, {}};
                bool hasNormals = !shape.normals.empty();
                for (size_t t = 0; t + 2 < shape.indices.size(); t += 3) {
                    uint32_t i0 = shape.indices[t], i1 = shape.indices[t + 1], i2 = shape.indices[t + 2];
                    glm::vec3 a = shape.positions[i0], b = shape.positions[i1], c = shape.positions[i2];
                    uint32_t normalsPlusOne = 0;
                    if (hasNormals) {
                        out.normals.push_back({glm::vec4(shape.normals[i0], 0.0f), glm::vec4(shape.normals[i1], 0.0f),
                                               glm::vec4(shape.normals[i2], 0.0f)});
                        normalsPlusOne = uint32_t(out.normals.size());
                    }
                    if (lightIndex != gpu::NO_LIGHT) {
                        mesh.prims.push_back(uint32_t(prims.size()));
                        mesh.areas.push_back(triangleArea(a, b, c));
                    }
                    prims.push_back(makePrimitive(gpu::PRIM_TRIANGLE, a, b, c, shape.material, lightIndex, normalsPlusOne));
                }
                if (lightIndex != gpu::NO_LIGHT) {
                    gpu::Light light = makeLight(gpu::LIGHT_MESH, shape.emission);
                    light.flags = flags;
                    double area = 0.0;
                    for (double a : mesh.areas) area += a;
                    light.area = float(area);
                    out.lights.push_back(light);
                    meshLights.push_back(std::move(mesh));
                }
                break;
            }
        }
    }

    out.bvh = buildBvh(std::move(prims), bvhOptions);

    // Input primitive index -> leaf-order index, for the lights' references.
    std::vector<uint32_t> leafIndex(out.bvh.originalIndex.size());
    for (uint32_t i = 0; i < out.bvh.originalIndex.size(); ++i) leafIndex[out.bvh.originalIndex[i]] = i;
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

    // Bounding sphere of the geometry (for the power of lights at infinity).
    const gpu::BvhNode& root = out.bvh.nodes.front();
    if (out.bvh.primitives.empty()) {
        out.boundsCenter = glm::vec3(0.0f);
        out.boundsRadius = 1.0f;
    } else {
        out.boundsCenter = 0.5f * (root.boundsMin + root.boundsMax);
        out.boundsRadius = std::max(0.5f * glm::length(root.boundsMax - root.boundsMin), 1e-6f);
    }

    // Light selection: the full table, then the delta-only and continuous-only sub-tables
    // built from the same weights (see RenderParams in shaders/shared/types.h).
    std::vector<double> weights;
    std::vector<uint32_t> items;
    std::vector<double> deltaWeights, continuousWeights;
    std::vector<uint32_t> deltaItems, continuousItems;
    for (uint32_t i = 0; i < out.lights.size(); ++i) {
        double w = scene.integrator.lightSelection == LightSelection::Power ? lightPower(out.lights[i], out.boundsRadius)
                                                                            : 1.0;
        weights.push_back(w);
        items.push_back(i);
        bool delta = out.lights[i].type == gpu::LIGHT_POINT || out.lights[i].type == gpu::LIGHT_DIRECTIONAL;
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
    return out;
}

gpu::RenderParams makeRenderParams(const Scene& scene, const SceneArrays& arrays) {
    gpu::RenderParams p{};
    const Camera& cam = scene.camera;
    glm::vec3 forward = glm::normalize(cam.target - cam.eye);
    glm::vec3 right = glm::normalize(glm::cross(forward, cam.up));
    glm::vec3 up = glm::cross(right, forward);
    p.eye = cam.eye;
    p.forward = forward;
    p.right = right;
    p.up = up;
    p.tanHalfFovY = std::tan(0.5f * glm::radians(cam.fovY));
    p.width = scene.film.width;
    p.height = scene.film.height;
    p.aspect = float(p.width) / float(p.height);
    p.seed = scene.sampler.seed;
    p.sampleOffset = scene.sampler.sampleOffset;
    const IntegratorSettings& in = scene.integrator;
    p.integrator = in.type == IntegratorType::AmbientOcclusion ? gpu::INTEGRATOR_AO : gpu::INTEGRATOR_DIRECT;
    p.lightCount = uint32_t(arrays.lights.size());
    p.aoMaxDistance = in.aoMaxDistance;
    p.nodeCount = uint32_t(arrays.bvh.nodes.size());
    p.deltaTableOffset = arrays.deltaTableOffset;
    p.deltaCount = arrays.deltaCount;
    p.continuousTableOffset = arrays.continuousTableOffset;
    p.continuousCount = arrays.continuousCount;
    p.deltaScale = arrays.deltaScale;
    p.continuousScale = arrays.continuousScale;
    p.environmentLight = arrays.environmentLight;
    return p;
}

}  // namespace penumbra
