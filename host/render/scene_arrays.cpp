// Scene -> GPU arrays: primitives, lights, materials and alias tables (see scene_arrays.h).
#include "render/scene_arrays.h"

#include <cmath>

#include "render/light_arrays.h"
#include "render/material_arrays.h"
#include "render/out_of_view.h"

namespace penumbra {
namespace {

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

// The shapes as primitives in input order, and the triangles of each mesh light.
struct ShapePrimitives {
    std::vector<gpu::Primitive> prims;
    std::vector<MeshLightTriangles> meshLights;
};

ShapePrimitives flattenShapes(const std::vector<Shape>& shapeList, SceneArrays& out);
void buildBvhAndMeshTables(ShapePrimitives shapes, const BvhOptions& bvhOptions, SceneArrays& out);
void setBounds(SceneArrays& out);

}  // namespace

SceneArrays buildSceneArrays(const Scene& scene, const BvhOptions& bvhOptions, EnvironmentTexels environmentTexels) {
    SceneArrays out;

    out.materials = packMaterials(scene.materials);

    // Lights without geometry first, then one light per emitting shape. Area lights record
    // their primitive's *input* index for now; it becomes the BVH leaf-order index below.
    appendLightsWithoutGeometry(scene.lights, out, environmentTexels);

    ShapePrimitives shapes = flattenShapes(scene.shapes, out);
    // Instanced groups: a tree each, and one primitive per instance in the scene's tree
    // (render/instance_arrays.h); none emits, so they add no lights.
    std::vector<std::vector<gpu::Primitive>> groupPrimitives;
    for (const InstancedGroup& group : scene.instancedGroups)
        groupPrimitives.push_back(flattenShapes(group.shapes, out).prims);
    std::vector<Bvh> groupTrees = buildGroupTrees(std::move(groupPrimitives), bvhOptions);
    appendInstancePrimitives(scene, groupTrees, shapes.prims);
    buildBvhAndMeshTables(std::move(shapes), bvhOptions, out);
    placeGroupTrees(scene, std::move(groupTrees), out.bvh, out.instanced);
    out.textures = buildTextureArrays(scene, out.bvh);
    setBounds(out);

    buildLightSelection(scene.integrator.lightSelection, out);
    if (scene.integrator.lightSelection == LightSelection::Bvh) buildLightBvhArrays(out);
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
    p.lightCount = uint32_t(arrays.lights.size());
    p.aoMaxDistance = in.aoMaxDistance;
    p.deltaTableOffset = arrays.deltaTableOffset;
    p.deltaCount = arrays.deltaCount;
    p.continuousTableOffset = arrays.continuousTableOffset;
    p.continuousCount = arrays.continuousCount;
    p.deltaScale = arrays.deltaScale;
    p.lightBvhTableOffset = arrays.lightBvh.tableOffset;
    p.lightBvhTableCount = arrays.lightBvh.tableCount;
    p.lightBvhItems = arrays.lightBvh.itemsTexel;
    p.lightBvhTrails = arrays.lightBvh.trailsTexel;
    p.continuousScale = arrays.continuousScale;
    p.environmentLight = arrays.environmentLight;
    p.besideFirst = arrays.bvh.besideFirst();
    p.besideCount = arrays.bvh.besideCount;
    p.cameraOutOfView = besideOutOfView(p, arrays.bvh);
    return p;
}

namespace {

// Shapes -> primitives, triangle normals (out.normals) and one light per emitting shape
// (appended to out.lights). Area lights record their primitive's *input* index for now.
ShapePrimitives flattenShapes(const std::vector<Shape>& shapeList, SceneArrays& out) {
    ShapePrimitives shapes;
    std::vector<gpu::Primitive>& prims = shapes.prims;
    std::vector<MeshLightTriangles>& meshLights = shapes.meshLights;
    for (const Shape& shape : shapeList) {
        uint32_t lightIndex = shape.isEmitter() ? uint32_t(out.lights.size()) : gpu::NO_LIGHT;
        switch (shape.type) {
            case ShapeType::Sphere: {
                if (lightIndex != gpu::NO_LIGHT) out.lights.push_back(makeSphereLight(shape, uint32_t(prims.size())));
                prims.push_back(makePrimitive(gpu::PRIM_SPHERE, shape.center, glm::vec3(shape.radius, 0, 0),
                                              glm::vec3(0.0f), shape.material, lightIndex));
                break;
            }
            case ShapeType::Quad: {
                if (lightIndex != gpu::NO_LIGHT) out.lights.push_back(makeQuadLight(shape, uint32_t(prims.size())));
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
                    double area = 0.0;
                    for (double a : mesh.areas) area += a;
                    out.lights.push_back(makeMeshLight(shape, area));
                    meshLights.push_back(std::move(mesh));
                }
                break;
            }
        }
    }
    return shapes;
}

// The BVH over the primitives; then the lights' primitive references go from input order to
// leaf order, and each mesh light's triangle alias table is appended to out.meshTable.
void buildBvhAndMeshTables(ShapePrimitives shapes, const BvhOptions& bvhOptions, SceneArrays& out) {
    out.bvh = buildBvh(std::move(shapes.prims), bvhOptions);

    // Input primitive index -> leaf-order index, for the lights' references.
    std::vector<uint32_t> leafIndex(out.bvh.originalIndex.size());
    for (uint32_t i = 0; i < out.bvh.originalIndex.size(); ++i) leafIndex[out.bvh.originalIndex[i]] = i;
    finishAreaLights(leafIndex, shapes.meshLights, out);
}

// Bounding sphere of the geometry (for the power of lights at infinity): the tree's and what
// is beside it (instances by their boxes).
void setBounds(SceneArrays& out) {
    if (out.bvh.primitives.empty()) {
        out.boundsCenter = glm::vec3(0.0f);
        out.boundsRadius = 1.0f;
    } else {
        const Aabb box = bvhBounds(out.bvh);
        out.boundsCenter = 0.5f * (box.lo + box.hi);
        out.boundsRadius = std::max(0.5f * glm::length(box.hi - box.lo), 1e-6f);
    }
}

}  // namespace

size_t geometryBytes(const SceneArrays& arrays) {
    return arrays.bvh.wideNodes.size() * sizeof(gpu::WideNode) +
           (arrays.bvh.primitives.size() + arrays.instanced.primitives.size()) * sizeof(gpu::Primitive) +
           arrays.normals.size() * sizeof(gpu::TriangleNormals) +
           arrays.instanced.instances.size() * sizeof(gpu::Instance);
}

}  // namespace penumbra
