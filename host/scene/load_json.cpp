// loadScene: reads a JSON scene file (or wraps a glTF model in a scene document), applies
// --set overrides, then validates and converts every section of SCENE_FORMAT.md into a
// Scene. Type and range checks come from JsonReader; glTF geometry from load_gltf.cpp.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <numbers>

#include "core/errors.h"
#include "core/input_file.h"
#include "scene/aov_names.h"
#include "scene/environment_file.h"
#include "scene/gltf_import.h"
#include "scene/integrator_options.h"
#include "scene/integrator_parse.h"
#include "scene/json_parse.h"
#include "scene/json_reader.h"
#include "scene/limits.h"
#include "scene/load.h"
#include "scene/material_parse.h"
#include "scene/material_textures.h"
#include "scene/mesh_file.h"
#include "scene/model_lighting.h"
#include "scene/scene_input_file.h"
#include "scene/shape_groups.h"
#include "scene/transform.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
constexpr float kPi = std::numbers::pi_v<float>;

// A position or size (limits.h): every component within [-1e8, 1e8].
glm::vec3 coordinates(const JsonReader& r) {
    glm::vec3 v = r.vec3();
    for (int c = 0; c < 3; ++c)
        if (std::fabs(v[c]) > float(kMaxCoordinate)) r[size_t(c)].fail("must be within [-1e8, 1e8] (README: ranges)");
    return v;
}

// A radiance, intensity or irradiance (limits.h): each component at most 1e20; `what`
// names it in the message.
glm::vec3 radiometric(const JsonReader& r, glm::vec3 value, const char* what) {
    // Compared as floats: 1e20 itself rounds up to the float 1.00000002e20.
    if (std::max({value.x, value.y, value.z}) > float(kMaxRadiometric))
        r.fail(std::string(what) + " exceeds 1e20 (README: ranges)");
    return value;
}

// The value of enum E that `r` names (integrator_options.h); the message lists the names.
template <class E>
E choiceOf(const JsonReader& r) {
    return *fromName<E>(r.choice(allNames<E>()));
}

// Total area of a triangle mesh; 0 when empty.
float meshArea(const Shape& s) {
    double area = 0.0;
    for (size_t t = 0; t + 2 < s.indices.size(); t += 3) {
        glm::vec3 a = s.positions[s.indices[t]], b = s.positions[s.indices[t + 1]], c = s.positions[s.indices[t + 2]];
        area += 0.5 * double(glm::length(glm::cross(b - a, c - a)));
    }
    return float(area);
}

class SceneBuilder {
public:
    SceneBuilder(Scene& scene, std::string label, fs::path baseDir, bool modelAlone)
        : m_scene(scene),
          m_label(std::move(label)),
          m_baseDir(std::move(baseDir)),
          m_modelAlone(modelAlone),
          m_textures(scene, m_baseDir) {}

    void build(const json& doc) {
        JsonReader root(doc, m_label);
        root.expectKeys({"camera", "film", "sampler", "integrator", "materials", "shapes", "lights"}, "a scene");
        if (auto film = root.find("film")) readFilm(*film);
        if (auto sampler = root.find("sampler")) readSampler(*sampler);
        m_scene.integrator = parseIntegrator(root.find("integrator"));
        readMaterials(root.find("materials"));
        if (auto shapes = root.find("shapes")) {
            // Groups first, so that an instance may come before the group it places.
            for (size_t i = 0; i < shapes->size(); ++i)
                if (isShapeOfType((*shapes)[i], "group")) readGroup((*shapes)[i]);
            checkInstancedPrimitives(*shapes, m_groups, [&](const Shape& s, const JsonReader& instance) {
                return copiedByInstances(s,
                                         instance.has("material") ? std::optional(materialOf(instance)) : std::nullopt);
            });
            for (size_t i = 0; i < shapes->size(); ++i) readShape((*shapes)[i]);
            noteUnusedGroups(m_groups, m_label, m_scene.notes);
        }
        if (auto lights = root.find("lights"))
            for (size_t i = 0; i < lights->size(); ++i) readLight((*lights)[i]);
        readCamera(root.find("camera"));
        // A model's own lights, or any given with --set lights=..., replace the studio lights
        // (`--set lights=[]` leaves a model lit by its emissive materials alone).
        if (m_modelAlone && m_scene.lights.empty() && !root.has("lights")) lightModel();
        else noteUnlitScene();
    }

private:
    void readFilm(const JsonReader& r) {
        r.expectKeys({"width", "height", "aovs"}, "film");
        if (auto w = r.find("width")) m_scene.film.width = uint32_t(w->integer(1, 16384));
        if (auto h = r.find("height")) m_scene.film.height = uint32_t(h->integer(1, 16384));
        if (auto a = r.find("aovs")) m_scene.film.aovs = readAovNames(*a);
    }

    void readSampler(const JsonReader& r) {
        r.expectKeys({"spp", "seed", "sample_offset", "type"}, "sampler");
        SamplerSettings& s = m_scene.sampler;
        // The EXR header records spp, seed and sample_offset as 32-bit signed ints
        // (SCENE_FORMAT.md "Output"), so each must fit one; then sample_offset + i never
        // wraps around in 32 bits either (partials stay disjoint).
        if (auto spp = r.find("spp")) s.spp = uint32_t(spp->integer(1, INT32_MAX));
        if (auto seed = r.find("seed")) s.seed = uint32_t(seed->integer(0, INT32_MAX));
        if (auto offset = r.find("sample_offset")) s.sampleOffset = uint32_t(offset->integer(0, INT32_MAX));
        if (auto type = r.find("type")) s.type = choiceOf<SamplerType>(*type);
    }

    void readMaterials(const std::optional<JsonReader>& r) {
        m_scene.materials = {Material{"default", MaterialType::Diffuse, glm::vec3(0.8f), glm::vec3(0.0f), 20.0f}};
        if (!r) return;
        for (const std::string& name : r->keys()) {
            JsonReader m = r->at(name.c_str());
            Material mat = parseMaterial(m, name, m_textures);
            m_materialIndex[name] = uint32_t(m_scene.materials.size());
            m_scene.materials.push_back(mat);
        }
    }

    uint32_t materialOf(const JsonReader& shape) const {
        auto r = shape.find("material");
        if (!r) return 0;
        std::string name = r->string();
        auto it = m_materialIndex.find(name);
        if (it == m_materialIndex.end()) r->fail("unknown material \"" + name + "\"");
        return it->second;
    }

    // `inGroup`: r is a shape of a group, which may not be a group or an instance itself.
    void readShape(const JsonReader& r, bool inGroup = false) {
        std::string type = r.at("type").choice({"sphere", "quad", "mesh", "gltf", "group", "instance"});
        if (inGroup && (type == "group" || type == "instance"))
            r.at("type").fail("a group holds spheres, quads, meshes and gltf shapes, not " + type +
                              "s (one level of instancing)");
        if (type == "group") return;  // read before the other shapes (build)
        if (type == "instance") return readInstance(r);
        if (type == "sphere")
            r.expectKeys({"type", "center", "radius", "material", "emission", "power", "to_world"}, "a sphere");
        if (type == "quad")
            r.expectKeys(
                {"type", "origin", "edge_u", "edge_v", "material", "emission", "power", "two_sided", "to_world"},
                "a quad");
        if (type == "mesh")
            r.expectKeys({"type", "positions", "indices", "normals", "uvs", "file", "material", "emission", "power",
                          "two_sided", "to_world"},
                         "a mesh");
        if (type == "gltf")
            r.expectKeys({"type", "file", "material", "emission", "power", "two_sided", "to_world"}, "a gltf shape");
        if (r.has("emission") && r.has("power")) r.fail("has both \"emission\" and \"power\"; give one");

        Shape s;
        s.material = materialOf(r);
        s.twoSided = r.has("two_sided") && r.at("two_sided").boolean();
        if (type == "gltf") return readGltfShape(r, s);
        if (type == "mesh" && r.has("file")) return readMeshFileShape(r, s);
        if (type == "sphere") {
            s.type = ShapeType::Sphere;
            s.center = coordinates(r.at("center"));
            s.radius = r.at("radius").number();
            if (!(s.radius > 0.0f)) r.at("radius").fail("must be > 0");
            if (s.radius > float(kMaxCoordinate)) r.at("radius").fail("must be at most 1e8 (README: ranges)");
        } else if (type == "quad") {
            s.type = ShapeType::Quad;
            s.origin = coordinates(r.at("origin"));
            s.edgeU = coordinates(r.at("edge_u"));
            s.edgeV = coordinates(r.at("edge_v"));
            const float area = glm::length(glm::cross(s.edgeU, s.edgeV));
            if (!(area > 0.0f) || !std::isfinite(area))
                r.fail("quad has zero or non-finite area (edge_u and edge_v must be non-zero and not parallel)");
        } else {
            readMesh(r, s);
        }
        applyToWorld(r, s);
        // The emitting area in the world, after to_world.
        const float area = s.type == ShapeType::Quad   ? glm::length(glm::cross(s.edgeU, s.edgeV))
                           : s.type == ShapeType::Mesh ? meshArea(s)
                                                       : 0.0f;
        s.emission = s.type == ShapeType::Sphere ? emissionOf(r, 4.0f * kPi * kPi * s.radius * s.radius)
                                                 : emissionOf(r, (s.twoSided ? 2.0f : 1.0f) * kPi * area);
        m_shapesOut->push_back(std::move(s));
    }

    // SCENE_FORMAT.md "groups and instances": a group's shapes, read once, into the group's
    // own frame (their own to_world applied); docs/design/contract-decisions.md, "Groups and
    // instances", says what is refused.
    void readGroup(const JsonReader& r) {
        r.expectKeys({"type", "name", "shapes"}, "a group");
        JsonReader nameField = r.at("name");
        std::string name = nameField.string();
        if (name.empty()) nameField.fail("a group's name must not be empty");
        if (m_groups.count(name)) nameField.fail("a second group named \"" + name + "\" (group names are unique)");
        JsonReader members = r.at("shapes");
        if (members.size() == 0) members.fail("a group needs at least one shape");
        ShapeGroup& group = m_groups[name];
        group.path = r.path();
        std::vector<Shape>* shapesOut = m_shapesOut;
        std::vector<Light>* lightsOut = m_lightsOut;
        m_shapesOut = &group.shapes;
        m_lightsOut = &group.lights;
        for (size_t i = 0; i < members.size(); ++i) readShape(members[i], true);
        m_shapesOut = shapesOut;
        m_lightsOut = lightsOut;
    }

    // An instance (SCENE_FORMAT.md "instance"): the group's shapes and lights moved by its
    // to_world after their own (instance o shape), with the instance's material in place of
    // theirs if it names one. Shapes that copiedByInstances says are copied join the scene's
    // shapes, moved; the others stay in the group's frame, traced through the group's own
    // tree (Scene::instances; render/instance_arrays.h), checked as their copies would be.
    // Emission stays the group's radiance (a scaled copy emits more power).
    void readInstance(const JsonReader& r) {
        r.expectKeys({"type", "of", "to_world", "material"}, "an instance");
        ShapeGroup& group = groupNamed(r.at("of"), m_groups);
        group.used = true;
        std::optional<uint32_t> material;
        if (r.has("material")) material = materialOf(r);
        auto field = r.find("to_world");
        const Affine m = field ? readToWorld(*field) : Affine{};
        bool traced = false;
        for (const Shape& member : group.shapes) {
            Shape s = member;
            if (material) s.material = *material;
            if (!copiedByInstances(member, material)) {
                if (field) checkMovedShape(*field, m, s);
                traced = true;
                continue;
            }
            if (field) moveShape(*field, m, s);
            m_shapesOut->push_back(std::move(s));
        }
        if (traced)
            m_scene.instances.push_back(
                {instancedGroupOf(group, material), m.linear, m.translation, material.value_or(kNoMaterialOverride)});
        for (Light light : group.lights) {
            if (field) {
                transformLight(m, light);
                if (!coordinateInRange(light.position))
                    field->fail("moves a light of the group outside [-1e8, 1e8] (README: ranges)");
            }
            m_lightsOut->push_back(light);
        }
    }

    // Whether an instance copies group shape s into the world (Scene::shapes) rather than
    // tracing it through the group's own tree: emitters (each copy is a light of its own),
    // and, as that traversal carries no per-primitive texture coordinates, tangents or ids,
    // shapes whose material (the instance's, if it names one) is textured, and every shape
    // of a scene with an id AOV layer (shape_id, primitive_id, material_id: they number the
    // copies; docs/design/contract-decisions.md, "Groups and instances").
    bool copiedByInstances(const Shape& s, std::optional<uint32_t> material) const {
        const auto isId = [](const std::string& layer) { return layer.ends_with("_id"); };
        if (s.isEmitter() || std::any_of(m_scene.film.aovs.begin(), m_scene.film.aovs.end(), isId)) return true;
        return !m_scene.materials[material.value_or(s.material)].textures.empty();
    }

    // The checks moveShape makes, for a shape that is traced, not copied: a sphere or quad
    // moved as a throwaway copy; a mesh's vertices moved one by one, into the range.
    void checkMovedShape(const JsonReader& field, const Affine& m, const Shape& s) const {
        if (s.type != ShapeType::Mesh) {
            Shape copy = s;
            return moveShape(field, m, copy);
        }
        for (glm::vec3 p : s.positions)
            if (!coordinateInRange(transformPoint(m, p)))
                field.fail("moves the mesh outside [-1e8, 1e8] (README: ranges)");
    }

    // The Scene::instancedGroups entry of `group`'s traced shapes: those without an
    // instance material, or those with one (an untextured one: all its non-emitters).
    uint32_t instancedGroupOf(ShapeGroup& group, std::optional<uint32_t> material) {
        int32_t& index = material ? group.tracedWithMaterial : group.tracedOwn;
        if (index < 0) {
            InstancedGroup traced;
            for (const Shape& s : group.shapes)
                if (!copiedByInstances(s, material)) traced.shapes.push_back(s);
            index = int32_t(m_scene.instancedGroups.size());
            m_scene.instancedGroups.push_back(std::move(traced));
        }
        return uint32_t(index);
    }

    // A shape's radiance: its `emission`, or its `power` over `powerPerRadiance`. Uniform
    // emitters, SCENE_FORMAT.md: P = Le * pi * A per emitting face (cosine-weighted hemisphere
    // integral), so Le = P/(pi A), or P/(2 pi A) with two faces; a sphere (A = 4 pi r^2, one
    // outward face) gives Le = P/(4 pi^2 r^2). Neither: 0.
    static glm::vec3 emissionOf(const JsonReader& r, float powerPerRadiance) {
        if (auto e = r.find("emission")) return radiometric(*e, e->color(), "radiance");
        auto p = r.find("power");
        if (!p) return glm::vec3(0.0f);
        const glm::vec3 emission = p->color() / powerPerRadiance;
        if (!std::isfinite(emission.x + emission.y + emission.z))
            p->fail("radiance from this power is not finite (the shape is too small)");
        return radiometric(*p, emission, "the radiance from this power");
    }

    // SCENE_FORMAT.md "to_world": the shape's data moved into the world when it loads (the
    // renderer never sees a transform), then checked again as the moved shape: ranges,
    // areas, and a sphere's only allowed map, a uniform scale with rotation and translation.
    void applyToWorld(const JsonReader& r, Shape& s) const {
        if (auto field = r.find("to_world")) moveShape(*field, readToWorld(*field), s);
    }

    // Shape s moved by m, the transform read from `field` (a shape's or an instance's
    // to_world), where the messages point.
    void moveShape(const JsonReader& field, const Affine& m, Shape& s) const {
        auto fail = [&](const std::string& why) { field.fail(why); };
        if (s.type == ShapeType::Sphere) {
            auto scale = uniformScaleOf(m);
            if (!scale) {
                const bool parts = field.json().is_object() && field.has("scale");
                (parts ? field.at("scale") : field)
                    .fail("a sphere takes only a uniform scale (besides rotation and translation)");
            }
            // A sphere has no orientation: the GPU maps its texture coordinates from world
            // directions, so a turned textured sphere would show its texture unturned.
            if (!turnsNothing(m) && !m_scene.materials[s.material].textures.empty())
                fail(
                    "rotates or mirrors a textured sphere, whose texture stays aligned with the world axes; "
                    "turn the texture's image or use a mesh");
            s.center = transformPoint(m, s.center);
            s.radius = float(*scale * double(s.radius));
            if (!coordinateInRange(s.center) || !(s.radius > 0.0f) || s.radius > float(kMaxCoordinate))
                fail("moves the sphere outside [-1e8, 1e8] (README: ranges)");
        } else if (s.type == ShapeType::Quad) {
            transformQuad(m, s);
            if (!coordinateInRange(s.origin) || !coordinateInRange(s.edgeU) || !coordinateInRange(s.edgeV))
                fail("moves the quad outside [-1e8, 1e8] (README: ranges)");
            const float area = glm::length(glm::cross(s.edgeU, s.edgeV));
            if (!(area > 0.0f) || !std::isfinite(area)) fail("leaves the quad with zero or non-finite area");
        } else {
            transformMesh(m, s);
            checkMovedMesh(field, s);
        }
    }

    // A mesh after its to_world: every position in range, every triangle still of some area.
    static void checkMovedMesh(const JsonReader& field, const Shape& s) {
        for (glm::vec3 p : s.positions)
            if (!coordinateInRange(p)) field.fail("moves the mesh outside [-1e8, 1e8] (README: ranges)");
        for (size_t t = 0; t + 2 < s.indices.size(); t += 3)
            if (auto why = triangleProblem(s.positions[s.indices[t]], s.positions[s.indices[t + 1]],
                                           s.positions[s.indices[t + 2]]))
                field.fail("leaves triangle " + std::to_string(t / 3) + " with zero or non-finite area");
    }

    void readMesh(const JsonReader& r, Shape& s) {
        s.type = ShapeType::Mesh;
        JsonReader positions = r.at("positions"), indices = r.at("indices");
        std::vector<float> p = positions.numbers();
        if (p.size() % 3 != 0) positions.fail("length " + std::to_string(p.size()) + " is not a multiple of 3");
        size_t vertices = p.size() / 3;
        for (size_t i = 0; i < p.size(); ++i)
            if (std::fabs(p[i]) > float(kMaxCoordinate))
                positions[i].fail("must be within [-1e8, 1e8] (README: ranges)");
        for (size_t v = 0; v < vertices; ++v) s.positions.emplace_back(p[3 * v], p[3 * v + 1], p[3 * v + 2]);

        size_t n = indices.size();
        if (n == 0) indices.fail("mesh has no triangles");
        if (n % 3 != 0) indices.fail("length " + std::to_string(n) + " is not a multiple of 3");
        s.indices.resize(n);
        for (size_t i = 0; i < n; ++i) {
            const json& v = indices.json()[i];
            int64_t index = v.is_number_unsigned() ? int64_t(std::min<uint64_t>(v.get<uint64_t>(), INT64_MAX))
                                                   : indices[i].integer(0, INT64_MAX);
            if (uint64_t(index) >= vertices)
                indices[i].fail("index " + std::to_string(index) + " out of range (" + std::to_string(vertices) + " vertices)");
            s.indices[i] = uint32_t(index);
        }
        for (size_t t = 0; t < n; t += 3)
            if (triangleProblem(s.positions[s.indices[t]], s.positions[s.indices[t + 1]],
                                s.positions[s.indices[t + 2]]))
                indices.fail("triangle " + std::to_string(t / 3) + " has zero or non-finite area");
        if (auto normals = r.find("normals")) {
            std::vector<float> nv = normals->numbers();
            if (nv.size() != p.size())
                normals->fail("has " + std::to_string(nv.size()) + " numbers, positions has " + std::to_string(p.size()));
            for (size_t v = 0; v < vertices; ++v) {
                auto unit = unitNormal(glm::vec3(nv[3 * v], nv[3 * v + 1], nv[3 * v + 2]));
                if (!unit) (*normals)[3 * v].fail("normal " + std::to_string(v) + " has zero length");
                s.normals.push_back(*unit);
            }
        }
        if (auto uvs = r.find("uvs")) {
            // Any finite values: outside [0, 1] the textures repeat.
            std::vector<float> uv = uvs->numbers();
            if (uv.size() != 2 * vertices)
                uvs->fail("has " + std::to_string(uv.size()) + " numbers, expected 2 per vertex (" +
                          std::to_string(2 * vertices) + ")");
            for (size_t v = 0; v < vertices; ++v) s.uvs.emplace_back(uv[2 * v], uv[2 * v + 1]);
        }
    }

    // SCENE_FORMAT.md "Mesh files": the file's parts (one per OBJ usemtl name) become mesh
    // shapes, each with the scene material of its usemtl name where the scene has one, else
    // the shape's own; emission and power as for one mesh over the parts' total area.
    void readMeshFileShape(const JsonReader& r, const Shape& settings) {
        for (const char* key : {"positions", "indices", "normals", "uvs"})
            if (r.has(key)) r.at(key).fail("a mesh with \"file\" takes its data from the file; give one or the other");
        JsonReader fileField = r.at("file");
        fs::path file = sceneRelativeInputFile(fileField, m_baseDir);
        std::vector<MeshPart> parts = readMeshFile(file, file.string());
        for (MeshPart& part : parts) applyToWorld(r, part.shape);
        float area = 0.0f;
        for (const MeshPart& part : parts) area += meshArea(part.shape);
        const glm::vec3 emission = emissionOf(r, (settings.twoSided ? 2.0f : 1.0f) * kPi * area);
        for (MeshPart& part : parts) {
            Shape& s = part.shape;
            auto named = m_materialIndex.find(part.material);
            s.material = !part.material.empty() && named != m_materialIndex.end() ? named->second : settings.material;
            s.emission = emission;
            s.twoSided = settings.twoSided;
            m_shapesOut->push_back(std::move(s));
        }
    }

    void readGltfShape(const JsonReader& r, const Shape& settings) {
        JsonReader fileField = r.at("file");
        // A model given on the command line is the user's own choice; one that a scene
        // names must lie in the scene's folder (docs/design/contract-decisions.md, "glTF file access").
        fs::path file = sceneRelativeInputFile(fileField, m_baseDir, !m_modelAlone);
        GltfImport model = importGltf(file, file.string());
        // to_world comes after the file's own node transforms, which importGltf applied, and
        // moves the file's lights with its meshes.
        for (Shape& s : model.shapes) applyToWorld(r, s);
        if (auto field = r.find("to_world")) {
            const Affine m = readToWorld(*field);
            for (Light& light : model.lights) {
                transformLight(m, light);
                if (!coordinateInRange(light.position))
                    field->fail("moves a light of the model outside [-1e8, 1e8] (README: ranges)");
            }
        }

        // The file's materials join the scene unless the shape names its own.
        uint32_t firstMaterial = uint32_t(m_scene.materials.size());
        bool ownMaterial = r.has("material");
        if (!ownMaterial) {
            // The model's textures join the scene's table (shared with any other user of
            // the same image, counted against the scene's limits).
            std::vector<uint32_t> textureIndex;
            for (Texture& t : model.textures) {
                std::string key = t.file;
                bool srgb = t.srgb;
                textureIndex.push_back(m_textures.table().add(
                    key, srgb, [&](const AcceptImageSize&) { return std::move(t); },
                    [&](const std::string& why) { fileField.fail(why); }));
            }
            for (Material& m : model.materials) {
                for (MaterialTexture& mt : m.textures) mt.texture = textureIndex[mt.texture];
                // The shape's own emission replaces the file's, its emissive texture too.
                if (r.has("emission") || r.has("power"))
                    std::erase_if(m.textures, [](const MaterialTexture& t) { return t.slot == TextureSlot::Emission; });
            }
            m_scene.materials.insert(m_scene.materials.end(), model.materials.begin(), model.materials.end());
        }
        glm::vec3 emission = r.has("emission") ? radiometric(r.at("emission"), r.at("emission").color(), "radiance")
                                               : glm::vec3(0.0f);
        if (auto p = r.find("power")) {
            // As for a mesh: the power spreads over the total area of all primitives.
            float area = 0.0f;
            for (const Shape& s : model.shapes) area += meshArea(s);
            emission = p->color() / ((settings.twoSided ? 2.0f : 1.0f) * kPi * area);
            if (!std::isfinite(emission.x + emission.y + emission.z)) p->fail("the model has no area to emit from");
            radiometric(*p, emission, "the radiance from this power");
        }
        for (size_t i = 0; i < model.shapes.size(); ++i) {
            Shape& s = model.shapes[i];
            int fileMaterial = model.shapeMaterials[i];
            s.material = ownMaterial ? settings.material : fileMaterial < 0 ? 0 : firstMaterial + uint32_t(fileMaterial);
            if (r.has("emission") || r.has("power")) s.emission = emission;
            if (r.has("two_sided")) s.twoSided = settings.twoSided;
            m_shapesOut->push_back(std::move(s));
        }
        m_lightsOut->insert(m_lightsOut->end(), model.lights.begin(), model.lights.end());
        m_scene.notes.insert(m_scene.notes.end(), model.notes.begin(), model.notes.end());
        if (!m_modelCamera) m_modelCamera = model.camera;
    }

    // One function per light kind (SCENE_FORMAT.md, "Lights"); each checks its own keys.
    void readLight(const JsonReader& r) {
        std::string type = r.at("type").choice({"point", "spot", "directional", "environment"});
        if (type == "point") m_scene.lights.push_back(readPointLight(r));
        else if (type == "spot") m_scene.lights.push_back(readSpotLight(r));
        else if (type == "directional") m_scene.lights.push_back(readDirectionalLight(r));
        else m_scene.lights.push_back(readEnvironmentLight(r));
    }

    Light readPointLight(const JsonReader& r) const {
        r.expectKeys({"type", "position", "power", "intensity"}, "a point light");
        Light light;
        light.type = LightType::Point;
        light.position = coordinates(r.at("position"));
        if (r.has("power") == r.has("intensity")) r.fail("give exactly one of \"power\" (W) and \"intensity\" (W/sr)");
        // Isotropic point light: I = P / (4 pi) W/sr.
        JsonReader given = r.at(r.has("power") ? "power" : "intensity");
        light.intensity =
            radiometric(given, r.has("power") ? given.color() / (4.0f * kPi) : given.color(), "intensity");
        return light;
    }

    // SCENE_FORMAT.md `spot`: angles in degrees from the axis, 0 <= inner < outer <= 90.
    Light readSpotLight(const JsonReader& r) const {
        r.expectKeys({"type", "position", "direction", "power", "intensity", "inner_angle", "outer_angle"},
                     "a spot light");
        Light light;
        light.type = LightType::Spot;
        light.position = coordinates(r.at("position"));
        JsonReader direction = r.at("direction");
        glm::vec3 d = direction.vec3();
        float len = glm::length(d);
        if (!(len > 0.0f) || !std::isfinite(len)) direction.fail("must be a non-zero vector");
        light.direction = d / len;
        double inner = r.has("inner_angle") ? r.at("inner_angle").number() : 0.0;
        double outer = r.has("outer_angle") ? r.at("outer_angle").number() : 45.0;
        if (!(outer > 0.0 && outer <= 90.0)) r.at("outer_angle").fail("must be in (0, 90] degrees");
        if (!(inner >= 0.0 && inner < outer))
            (r.has("inner_angle") ? r.at("inner_angle") : r).fail("must be in [0, outer_angle) degrees");
        double cosInner = std::cos(inner * std::numbers::pi / 180.0),
               cosOuter = std::cos(outer * std::numbers::pi / 180.0);
        // Angles that differ by less than a float can tell apart would leave no falloff band.
        if (!(float(cosOuter) < float(cosInner))) r.fail("inner_angle and outer_angle are too close to tell apart");
        light.cosInner = float(cosInner);
        light.cosOuter = float(cosOuter);
        if (r.has("power") == r.has("intensity")) r.fail("give exactly one of \"power\" (W) and \"intensity\" (W/sr)");
        JsonReader given = r.at(r.has("power") ? "power" : "intensity");
        // Power P = I * (integral of the falloff over the sphere): I = P / that.
        double perIntensity = spotFalloffIntegral(light.cosInner, light.cosOuter);
        light.intensity =
            radiometric(given, r.has("power") ? given.color() / float(perIntensity) : given.color(), "intensity");
        return light;
    }

    Light readDirectionalLight(const JsonReader& r) const {
        r.expectKeys({"type", "direction", "irradiance"}, "a directional light");
        Light light;
        light.type = LightType::Directional;
        JsonReader direction = r.at("direction");
        glm::vec3 d = direction.vec3();
        float len = glm::length(d);
        if (!(len > 0.0f) || !std::isfinite(len)) direction.fail("must be a non-zero vector");
        light.direction = d / len;
        light.intensity = radiometric(r.at("irradiance"), r.at("irradiance").color(), "irradiance");
        return light;
    }

    Light readEnvironmentLight(const JsonReader& r) const {
        r.expectKeys({"type", "radiance", "file"}, "an environment light");
        Light light;
        light.type = LightType::Environment;
        light.intensity = r.has("radiance") ? radiometric(r.at("radiance"), r.at("radiance").color(), "radiance")
                                            : glm::vec3(1.0f);
        bool second = std::any_of(m_scene.lights.begin(), m_scene.lights.end(),
                                  [](const Light& l) { return l.type == LightType::Environment; });
        if (second) r.fail("only one environment light is allowed");
        if (auto file = r.find("file")) light.map = readEnvironmentFile(*file, m_baseDir, light.intensity);
        return light;
    }

    // A model rendered on its own has no camera in a scene file: use its own first camera,
    // else frame the scene bounds. Fields given with --set replace those of either.
    Camera automaticCamera(const std::optional<JsonReader>& r) const {
        float fovY = r && r->has("fov_y") ? r->at("fov_y").number() : m_modelCamera ? m_modelCamera->fovY : 40.0f;
        if (m_modelCamera) return Camera{m_modelCamera->eye, m_modelCamera->target, m_modelCamera->up, fovY};
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        auto grow = [&](glm::vec3 p) { lo = glm::min(lo, p); hi = glm::max(hi, p); };
        for (const Shape& s : m_scene.shapes) {
            if (s.type == ShapeType::Sphere) {
                grow(s.center - s.radius);
                grow(s.center + s.radius);
            } else if (s.type == ShapeType::Quad) {
                for (glm::vec3 p : {s.origin, s.origin + s.edgeU, s.origin + s.edgeV, s.origin + s.edgeU + s.edgeV}) grow(p);
            }
            for (glm::vec3 p : s.positions) grow(p);
        }
        Camera c;
        c.fovY = fovY;
        if (!(lo.x <= hi.x)) return c;  // nothing to frame
        glm::vec3 center = 0.5f * (lo + hi);
        float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
        // The bounding sphere fits a cone of half-angle theta when the eye is radius/sin(theta)
        // away; theta is the smaller of the vertical and horizontal half fields of view.
        float tanHalf = std::tan(glm::radians(std::clamp(fovY, 1.0f, 179.0f)) * 0.5f);
        float aspect = float(m_scene.film.width) / float(m_scene.film.height);
        float theta = std::atan(tanHalf * std::min(1.0f, aspect));
        // A three-quarter view, as model viewers and product shots frame an object: from the
        // front-right (+Z and +X, 45 degrees round the vertical) and 30 degrees above, so that a
        // box shows three faces instead of one flat square.
        const float azimuth = glm::radians(45.0f), elevation = glm::radians(30.0f);
        glm::vec3 from(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                       std::cos(elevation) * std::cos(azimuth));
        c.target = center;
        c.eye = center + from * (radius / std::sin(theta));
        c.up = {0.0f, 1.0f, 0.0f};
        return c;
    }

    void readCamera(const std::optional<JsonReader>& r) {
        Camera c = m_modelAlone ? automaticCamera(r) : Camera{};
        if (r) {
            r->expectKeys({"eye", "target", "up", "fov_y"}, "camera");
            if (auto eye = r->find("eye")) c.eye = coordinates(*eye);
            if (auto target = r->find("target")) c.target = coordinates(*target);
            c.up = r->vec3Or("up", c.up);
            c.fovY = r->numberOr("fov_y", c.fovY);
        }
        auto fail = [&](const char* key, const std::string& why) {
            throwInputError(m_label, joinPath(r ? r->path() : "camera", key), why);
        };
        if (!(c.fovY > 0.0f && c.fovY < 180.0f)) fail("fov_y", "must be in (0, 180) degrees");
        glm::vec3 view = c.target - c.eye;
        if (!(glm::length(view) > 0.0f) || !std::isfinite(glm::length(view))) fail("target", "must differ from eye");
        glm::vec3 side = glm::cross(glm::normalize(view), c.up);
        if (!(glm::length(side) > 1e-6f * glm::length(c.up)) || !std::isfinite(glm::length(side)))
            fail("up", "must be non-zero and not parallel to the view direction");
        m_scene.camera = c;
    }

    // SCENE_FORMAT.md "glTF input": a model without lights would render black, or lit by its
    // emissive materials alone (ClearCoatTest's labels), where a model viewer shows it lit.
    void lightModel() {
        m_scene.lights = modelStudioLights(m_scene.camera);
        m_scene.notes.push_back(m_label + ": " + modelStudioLightsNote());
    }

    // SCENE_FORMAT.md "Output": a scene file with nothing that emits renders black; say so.
    // Ambient occlusion needs no lights, so it gets no note.
    void noteUnlitScene() {
        if (m_scene.integrator.type != IntegratorType::Direct || !m_scene.lights.empty()) return;
        if (std::any_of(m_scene.shapes.begin(), m_scene.shapes.end(), [](const Shape& s) { return s.isEmitter(); }))
            return;
        m_scene.notes.push_back(m_label + ": no lights and no emitting shapes; the image will be black");
    }

    Scene& m_scene;
    std::string m_label;
    fs::path m_baseDir;
    bool m_modelAlone;  // a glTF model given on its own, wrapped in a scene document
    std::map<std::string, uint32_t> m_materialIndex;
    std::optional<Camera> m_modelCamera;
    MaterialTextureReader m_textures;  // after m_baseDir, which it is built from
    // Where readShape puts what it reads: the scene's shapes and lights, or a group's.
    std::vector<Shape>* m_shapesOut = &m_scene.shapes;
    std::vector<Light>* m_lightsOut = &m_scene.lights;
    std::map<std::string, ShapeGroup> m_groups;  // by name
};

}  // namespace

json readJsonFile(const fs::path& file, const std::string& label) {
    return parseJsonText(readInputFile(file, label, kMaxJsonFileBytes), label);
}

SceneDocument readSceneDocument(const fs::path& file) {
    SceneDocument document;
    document.label = file.string();
    document.baseDir = file.parent_path();
    document.name = file.stem().string();
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    // A glTF model given on its own (not a scene file that names one).
    document.modelAlone = ext == ".gltf" || ext == ".glb";
    if (document.modelAlone) {
        if (auto problem = openProblem(file))
            throwInputError(document.label, "", "cannot open file (" + *problem + ")");
        document.doc = {{"shapes", json::array({{{"type", "gltf"}, {"file", file.filename().string()}}})}};
    } else {
        document.doc = readJsonFile(file, document.label);
    }
    return document;
}

Scene buildScene(const SceneDocument& document) {
    Scene scene;
    scene.path = document.label;
    scene.name = document.name;
    try {
        SceneBuilder(scene, document.label, document.baseDir, document.modelAlone).build(document.doc);
    } catch (const json::exception& e) {
        // Not expected (JsonReader checks types first); still bad input, never a crash.
        throwInputError(document.label, "", e.what());
    }
    return scene;
}

Scene loadScene(const fs::path& file, const std::vector<Override>& overrides) {
    SceneDocument document = readSceneDocument(file);
    for (const Override& o : overrides) applyOverride(document.doc, o);
    return buildScene(document);
}

}  // namespace penumbra
