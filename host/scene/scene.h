// The in-memory scene: what the loaders (JSON, glTF) produce and the renderer consumes.
// Plain data with no Vulkan types; every value here has already been validated, so the
// flattening for the GPU (render/scene_arrays.cpp) never has to check anything again.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/integrator_options.h"

namespace penumbra {

struct Camera {
    glm::vec3 eye{0.0f, 1.0f, 5.0f};
    glm::vec3 target{0.0f, 1.0f, 0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovY = 40.0f;  // full vertical field of view, degrees
};

struct Film {
    uint32_t width = 512;
    uint32_t height = 512;
    // film.aovs (SCENE_FORMAT.md "AOVs (v3)"): layer names, checked and in the file's order.
    std::vector<std::string> aovs;

    bool operator==(const Film&) const = default;
};

struct SamplerSettings {
    uint32_t spp = 16;
    uint32_t seed = 0;
    uint32_t sampleOffset = 0;
    SamplerType type = SamplerType::Sobol;
};

enum class MaterialType { Diffuse, Phong, Pbr };

// The `pbr` material's factors (SCENE_FORMAT.md v2, glTF metallic-roughness), each in [0, 1].
struct PbrFactors {
    glm::vec3 baseColor{0.8f};
    float metallic = 0.0f;
    float roughness = 0.5f;

    bool operator==(const PbrFactors&) const = default;
};

// Which value of a material a texture replaces: the GPU Material's slots (TEXTURE_SLOT_*
// in shaders/shared/types.h say which material field each one is). Emission is no field of
// the Material: it scales the emitted radiance of the primitives that use the material
// (glTF emissiveTexture).
// Alpha is the alpha test of glTF's alphaMode MASK: scale.x the alpha factor, scale.y the
// cutoff, the texture's channel 3 (TEXTURE_SLOT_ALPHA in shaders/shared/types.h).
// Normal is a tangent-space normal map (glTF normalTexture): scale.x its scale; the meshes
// that use the material carry per-vertex tangents (Shape::tangents).
enum class TextureSlot { Kd, Ks, KsX, KsY, Emission, Alpha, Normal };

// How a texture continues outside [0, 1] (glTF 2.0 section 5.26, samplers): REPEAT,
// CLAMP_TO_EDGE and MIRRORED_REPEAT. Numbered as TEXTURE_WRAP_* in shaders/shared/types.h.
enum class TextureWrap { Repeat, Clamp, Mirror };

// An affine map of texture coordinates, applied before the lookup (glTF's
// KHR_texture_transform): (u', v') = (dot(u, (u, v, 1)), dot(v, (u, v, 1))). The default is
// the identity, which the GPU never evaluates (render/texture_arrays.cpp).
struct UvTransform {
    glm::vec3 u{1.0f, 0.0f, 0.0f}, v{0.0f, 1.0f, 0.0f};

    bool isIdentity() const { return *this == UvTransform{}; }
    bool operator==(const UvTransform&) const = default;
};

// A textured field (SCENE_FORMAT.md "Textures (v2)"): the value is scale times the
// texture at the point's (u, v), channel `channel` alone for a number field.
struct MaterialTexture {
    TextureSlot slot = TextureSlot::Kd;
    uint32_t texture = 0;   // index into Scene::textures
    glm::vec3 scale{1.0f};  // a number field uses scale.x
    uint32_t channel = 0;   // number fields: which channel (0 = R ... 3 = A)
    // Wrapping along u and v (glTF samplers; a JSON texture repeats, SCENE_FORMAT.md).
    TextureWrap wrapU = TextureWrap::Repeat, wrapV = TextureWrap::Repeat;
    UvTransform uvTransform;  // glTF KHR_texture_transform; identity elsewhere

    bool operator==(const MaterialTexture&) const = default;
};

struct Material {
    std::string name;
    MaterialType type = MaterialType::Diffuse;
    glm::vec3 kd{0.8f};                     // diffuse: albedo; phong: kd
    glm::vec3 ks{0.0f};                     // phong
    float exponent = 20.0f;                 // phong
    PbrFactors pbr;                         // pbr
    std::vector<MaterialTexture> textures;  // fields given as textures, each slot at most once

    bool operator==(const Material&) const = default;
};

// A decoded texture image: linear RGBA, already rounded to the half floats the GPU holds
// (render/texture_arrays.h), row 0 = the image's top row = v 0.
struct Texture {
    std::string file;   // as resolved from the scene, for messages
    bool srgb = false;  // 8/16-bit data was sRGB-decoded (colour fields)
    uint32_t width = 0, height = 0;
    std::vector<uint16_t> texels;  // width * height * 4 half floats (RGBA), row-major

    bool operator==(const Texture&) const = default;
};

enum class ShapeType { Sphere, Quad, Mesh };

// One geometric shape after loading; glTF shapes are already expanded into Mesh shapes
// with transforms applied. Emission is radiance (W/(sr m^2)); `power` was converted.
struct Shape {
    ShapeType type = ShapeType::Mesh;
    uint32_t material = 0;       // index into Scene::materials
    glm::vec3 emission{0.0f};    // radiance; all zero = not a light
    bool twoSided = false;       // quad / mesh lights: emit from both faces
    // sphere
    glm::vec3 center{0.0f};
    float radius = 0.0f;
    // quad: origin + s*edgeU + t*edgeV, s,t in [0,1]; front normal = normalize(edgeU x edgeV)
    glm::vec3 origin{0.0f}, edgeU{0.0f}, edgeV{0.0f};
    // mesh: counter-clockwise triangles are front-facing; normals are per vertex or empty
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> uvs;  // per vertex or empty (then uv 0 everywhere)
    // Per vertex or empty: unit tangent xyz and bitangent sign w = +-1 (B = w cross(N, T),
    // glTF 2.0 section 3.7.2.1), for normal-mapped meshes (host/scene/tangents.h).
    std::vector<glm::vec4> tangents;

    bool isEmitter() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }

    bool operator==(const Shape&) const = default;
};

// Groups and instances traced as instances (SCENE_FORMAT.md "instance"; a two-level BVH,
// render/instance_arrays.h): a group's shapes that no instance copies, in the group's own
// frame, built once into a BVH of their own. None of them emits (emitting shapes of a group
// are copied into Scene::shapes, one light per instance) and none is textured (those are
// copied too: docs/design/contract-decisions.md, "Groups and instances").
struct InstancedGroup {
    std::vector<Shape> shapes;

    bool operator==(const InstancedGroup&) const = default;
};

inline constexpr uint32_t kNoMaterialOverride = 0xffffffffu;

// One placement of an InstancedGroup: its to_world, x' = linear x + translation (already
// checked: invertible, a sphere's uniform, the moved bounds in range).
struct Instance {
    uint32_t group = 0;  // index into Scene::instancedGroups
    glm::dmat3 linear{1.0};
    glm::dvec3 translation{0.0};
    uint32_t material = kNoMaterialOverride;  // the instance's `material`, else each shape's own

    bool operator==(const Instance&) const = default;
};

enum class LightType { Point, Directional, Environment, Spot };

// An equirectangular environment map (SCENE_FORMAT.md `environment` with `file`) as loaded:
// linear RGB radiance, row 0 at the top (+y), `width` columns around the vertical axis.
struct EnvironmentImage {
    uint32_t width = 0, height = 0;
    std::vector<glm::vec3> texels;  // width * height, row by row

    bool operator==(const EnvironmentImage&) const = default;
};

// Lights without geometry. Area lights are Shapes with emission.
struct Light {
    LightType type = LightType::Point;
    glm::vec3 position{0.0f};   // point, spot
    glm::vec3 direction{0.0f};  // directional: unit direction the light travels; spot: unit axis
    glm::vec3 intensity{0.0f};  // point: W/sr; spot: W/sr on the axis; directional: irradiance W/m^2;
                                // environment: radiance
    float cosInner = 1.0f;      // spot: cosines of the inner and outer angles, cosOuter < cosInner
    float cosOuter = 0.0f;
    // environment with `file`: the map, its texels already multiplied by `intensity` (the
    // radiance; finite and non-negative), shared so that copies of the scene do not copy
    // it; null for a constant sky.
    std::shared_ptr<const EnvironmentImage> map;

    // Equal maps by content: a scene loaded again holds its own copy of the same map.
    bool operator==(const Light& other) const {
        const bool sameMap = map == other.map || (map && other.map && *map == *other.map);
        return type == other.type && position == other.position && direction == other.direction &&
               intensity == other.intensity && cosInner == other.cosInner && cosOuter == other.cosOuter && sameMap;
    }
};

// Integral over the sphere of a spot light's falloff s^2 (SCENE_FORMAT.md `spot`): the full
// cone 2 pi (1 - cos inner), and the band where s is linear in cos t, 2 pi (cos inner -
// cos outer) / 3. A spot of intensity I on its axis emits I times this (W).
inline double spotFalloffIntegral(double cosInner, double cosOuter) {
    return 2.0 * 3.14159265358979323846 * ((1.0 - cosInner) + (cosInner - cosOuter) / 3.0);
}

struct Scene {
    std::string path;  // file it was loaded from, for messages
    std::string name;  // file stem, used for the default output name
    Camera camera;
    Film film;
    SamplerSettings sampler;
    IntegratorSettings integrator;
    std::vector<Material> materials;  // index 0 is always the default diffuse 0.8
    std::vector<Shape> shapes;
    std::vector<InstancedGroup> instancedGroups;  // groups placed by instances, not copied
    std::vector<Instance> instances;
    std::vector<Light> lights;
    std::vector<Texture> textures;  // every distinct (file, decoding) the materials use
    // One-line notes for the user (stderr unless --quiet), e.g. that an unlit glTF model
    // is lit by a white environment instead.
    std::vector<std::string> notes;
};

// True when a renderer that uploaded `uploaded` can render `next` by changing only its
// render parameters (Renderer::retarget): what the GPU holds, the film, the geometry,
// materials, lights (their tables depend on integrator.light_selection) and textures, is
// equal in content. By content, not by file name: a scene file edited during a batch is
// uploaded anew (reusing by path rendered the old content).
inline bool sharesUpload(const Scene& uploaded, const Scene& next) {
    return uploaded.film.width == next.film.width && uploaded.film.height == next.film.height &&
           uploaded.film.aovs == next.film.aovs &&
           uploaded.integrator.lightSelection == next.integrator.lightSelection &&
           uploaded.materials == next.materials && uploaded.shapes == next.shapes &&
           uploaded.instancedGroups == next.instancedGroups && uploaded.instances == next.instances &&
           uploaded.lights == next.lights && uploaded.textures == next.textures;
}

}  // namespace penumbra
