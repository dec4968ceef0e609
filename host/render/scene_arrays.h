// Flattens a Scene into the arrays the render kernels read (shaders/shared/types.h):
// primitives in BVH order, materials, lights and the two alias tables. Pure CPU work done
// once per scene; uploading is the Renderer's job.
#pragma once

#include <vector>

#include "bvh/bvh.h"
#include "render/instance_arrays.h"
#include "render/light_bvh_arrays.h"
#include "render/texture_arrays.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace penumbra {

struct SceneArrays {
    Bvh bvh;                   // nodes + primitives (leaf order); the groups' nodes follow
    InstanceArrays instanced;  // instances and their groups' primitives (two-level BVH)
    std::vector<gpu::TriangleNormals> normals;
    std::vector<gpu::Material> materials;
    std::vector<gpu::Light> lights;
    std::vector<gpu::AliasEntry> lightTable;    // light selection
    std::vector<gpu::AliasEntry> meshTable;     // triangles of all mesh lights, light by light
    uint32_t deltaTableOffset = 0, deltaCount = 0;            // sub-tables of lightTable
    uint32_t continuousTableOffset = 0, continuousCount = 0;
    float deltaScale = 0.0f, continuousScale = 0.0f;
    uint32_t environmentLight = gpu::NO_LIGHT;
    LightBvhArrays lightBvh;  // light_selection "bvh" only (else empty)
    // The environment's map (render/environment_map.h), if it has one: radiance per texel
    // (alpha unused) and the alias table that samples the texels. Empty for a constant sky
    // (and the texels when buildSceneArrays was told to leave them out).
    std::vector<glm::vec4> environmentTexels;
    std::vector<gpu::AliasEntry> environmentTable;
    TextureArrays textures;                     // material textures and mesh uvs
    glm::vec3 boundsCenter{0.0f};               // bounding sphere of the geometry
    float boundsRadius = 0.0f;
};

// Whether an environment map's texels go into SceneArrays::environmentTexels, or are left
// out for the Renderer, which writes them straight into GPU memory (writeEnvironmentTexels):
// up to 512 MiB of host memory less while it loads.
enum class EnvironmentTexels { InArrays, LeftOut };

SceneArrays buildSceneArrays(const Scene& scene, const BvhOptions& bvhOptions = {},
                             EnvironmentTexels environmentTexels = EnvironmentTexels::InArrays);

// Bytes of the geometry on the GPU: wide nodes, primitives (the groups' too), triangle
// normals and instances.
size_t geometryBytes(const SceneArrays& arrays);

// The RenderParams for a scene (camera basis, film, sampler, light tables); integrator
// options that select code are specialization constants (render/kernel_options.h).
gpu::RenderParams makeRenderParams(const Scene& scene, const SceneArrays& arrays);

}  // namespace penumbra
