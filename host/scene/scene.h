// The in-memory scene: what the loaders (JSON, glTF) produce and the renderer consumes.
// Plain data with no Vulkan types; every value here has already been validated, so the
// GPU upload (render/gpu_scene.cpp) never has to check anything again.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

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
};

// How a pixel's samples are placed (shaders/common/rng.glsl). Sobol' is the default, as
// low-discrepancy samplers are in pbrt-v4 and Cycles: unbiased like independent samples,
// with lower error on smooth integrands.
enum class SamplerType { Independent, Sobol };

struct SamplerSettings {
    uint32_t spp = 16;
    uint32_t seed = 0;
    uint32_t sampleOffset = 0;
    SamplerType type = SamplerType::Sobol;
};

// The scene-file name of a sampler type ("independent", "sobol").
inline const char* samplerTypeName(SamplerType type) {
    return type == SamplerType::Sobol ? "sobol" : "independent";
}

enum class IntegratorType { AmbientOcclusion, Direct };
enum class AoSampling { Uniform, Cosine };
enum class Strategy { Light, Bsdf, Mis, Mixture };
enum class Heuristic { Balance, Power };
enum class SphereSampling { Area, Cap, SolidAngle };
enum class QuadSampling { Area, SolidAngle };
enum class TriangleSampling { Area, SolidAngle };
enum class LightSelection { Uniform, Power };

struct IntegratorSettings {
    IntegratorType type = IntegratorType::Direct;
    // ao
    AoSampling aoSampling = AoSampling::Cosine;
    float aoMaxDistance = 1e30f;
    // direct
    Strategy strategy = Strategy::Mis;
    Heuristic heuristic = Heuristic::Power;
    uint32_t lightSamples = 1;
    uint32_t bsdfSamples = 1;
    SphereSampling sphereSampling = SphereSampling::SolidAngle;
    QuadSampling quadSampling = QuadSampling::SolidAngle;
    TriangleSampling triangleSampling = TriangleSampling::Area;
    LightSelection lightSelection = LightSelection::Power;
    // The integrator object as written (after --set overrides), with defaults filled in,
    // for the EXR header attribute penumbra:integrator.
    nlohmann::json json;
};

enum class MaterialType { Diffuse, Phong, Pbr };

// The `pbr` material's factors (SCENE_FORMAT.md v2, glTF metallic-roughness), each in [0, 1].
struct PbrFactors {
    glm::vec3 baseColor{0.8f};
    float metallic = 0.0f;
    float roughness = 0.5f;
};

struct Material {
    std::string name;
    MaterialType type = MaterialType::Diffuse;
    glm::vec3 kd{0.8f};      // diffuse: albedo; phong: kd
    glm::vec3 ks{0.0f};      // phong
    float exponent = 20.0f;  // phong
    PbrFactors pbr;          // pbr
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

    bool isEmitter() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
};

enum class LightType { Point, Directional, Environment };

// Lights without geometry. Area lights are Shapes with emission.
struct Light {
    LightType type = LightType::Point;
    glm::vec3 position{0.0f};   // point
    glm::vec3 direction{0.0f};  // directional: unit direction the light travels
    glm::vec3 intensity{0.0f};  // point: W/sr; directional: irradiance W/m^2; environment: radiance
};

struct Scene {
    std::string path;  // file it was loaded from, for messages
    std::string name;  // file stem, used for the default output name
    Camera camera;
    Film film;
    SamplerSettings sampler;
    IntegratorSettings integrator;
    std::vector<Material> materials;  // index 0 is always the default diffuse 0.8
    std::vector<Shape> shapes;
    std::vector<Light> lights;
    // One-line notes for the user (stderr unless --quiet), e.g. that an unlit glTF model
    // is lit by a white environment instead.
    std::vector<std::string> notes;
};

}  // namespace penumbra
