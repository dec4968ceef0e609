// glTF 2.0 import (.gltf and .glb) through tinygltf: triangle primitives with node
// transforms and TEXCOORD_0, materials (metallic-roughness factors and textures as `pbr`,
// textures in gltf_textures.cpp; emission), KHR_lights_punctual lights and the
// first camera. Every index, offset and count from the file is bounds-checked here, since
// tinygltf leaves most of that to its caller. Joining the result to a Scene is load_json.cpp's.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "core/errors.h"
#include "core/input_file.h"
#include "scene/gltf_extensions.h"
#include "scene/gltf_import.h"
#include "scene/gltf_input_rules.h"
#include "scene/gltf_textures.h"
#include "scene/limits.h"
#include "scene/tangents.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// The first line of a tinygltf message, without nlohmann's "[json.exception...] parse error at" prefix.
std::string firstLine(const std::string& text) {
    size_t start = text.find_first_not_of(" \t\r\n");
    if (start == std::string::npos) return {};
    size_t end = text.find_first_of("\r\n", start);
    std::string line = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (line.rfind("[json.exception.", 0) == 0) {
        size_t at = line.find("line ");
        line = at != std::string::npos ? line.substr(at) : line.substr(std::min(line.size(), line.find("] ") + 2));
    }
    return elideWords(line);
}

std::string at(const char* array, size_t index) { return std::string(array) + "[" + std::to_string(index) + "]"; }

// A bounds-checked view of an accessor's elements (component type and count as stored).
struct AccessorView {
    const unsigned char* data = nullptr;  // null: no bufferView, all zeros (glTF 2.0 §5.1)
    size_t stride = 0, count = 0;
    int componentType = 0, components = 0, componentSize = 0;
    bool normalized = false;

    // Component c of element i as a double; normalized integers map to [0,1] / [-1,1]
    // (glTF 2.0 §3.11, "Animations"/"Meshes" normalized integer formulas).
    double get(size_t i, int c) const {
        if (!data) return 0.0;
        const unsigned char* p = data + i * stride + size_t(c) * componentSize;
        auto load = [p](auto value) { std::memcpy(&value, p, sizeof value); return value; };
        switch (componentType) {
            case TINYGLTF_COMPONENT_TYPE_BYTE: {
                double x = load(int8_t{});
                return normalized ? std::max(x / 127.0, -1.0) : x;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
                double x = load(uint8_t{});
                return normalized ? x / 255.0 : x;
            }
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                double x = load(int16_t{});
                return normalized ? std::max(x / 32767.0, -1.0) : x;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                double x = load(uint16_t{});
                return normalized ? x / 65535.0 : x;
            }
            case TINYGLTF_COMPONENT_TYPE_INT: return load(int32_t{});
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
                double x = load(uint32_t{});
                return normalized ? x / 4294967295.0 : x;
            }
            case TINYGLTF_COMPONENT_TYPE_FLOAT: return load(float{});
            default: return load(double{});
        }
    }
    glm::dvec3 vec3(size_t i) const { return {get(i, 0), get(i, 1), get(i, 2)}; }
};

class Importer {
public:
    Importer(const tinygltf::Model& model, std::string label, const GltfImageBytes& images)
        : m_model(model),
          m_label(std::move(label)),
          m_textures(model, m_label, images, m_result.textures, m_result.notes) {}

    GltfImport run();

private:
    [[noreturn]] void fail(const std::string& path, const std::string& message) const {
        throwInputError(m_label, path, message);
    }
    void note(const std::string& text) { m_result.notes.push_back(m_label + ": " + text); }

    AccessorView view(int index, const std::string& usedAt, int expectedType);
    glm::dmat4 localTransform(const tinygltf::Node& node, const std::string& path) const;
    void checkHierarchy() const;
    void loadMaterials();
    bool readAlphaMode(const tinygltf::Material& mat, const std::string& path, bool emissive,
                       const std::optional<MaterialTexture>& baseColor, Material& m);
    Material metallicRoughnessMaterial(const tinygltf::Material& mat, const std::string& path) const;
    void addPrimitive(const tinygltf::Primitive& prim, const glm::dmat4& world, const std::string& path);
    void readTangents(int accessor, size_t count, const glm::dmat4& world, const std::string& path, Shape& shape);
    void addLight(const tinygltf::Node& node, const glm::dmat4& world, const std::string& path);
    Light pointLight(const glm::dmat4& world, const std::string& path);
    Light spotLight(const tinygltf::Light& src, const glm::dmat4& world, const std::string& path,
                    const std::string& lightPath);
    Light directionalLight(const glm::dmat4& world, const std::string& path);
    glm::vec3 lightAxis(const glm::dmat4& world, const std::string& path);
    void addCamera(const tinygltf::Node& node, const glm::dmat4& world, const std::string& path);

    const tinygltf::Model& m_model;
    std::string m_label;
    GltfImport m_result;
    GltfTextureReader m_textures;       // after m_label and m_result, which it refers to
    std::vector<glm::vec3> m_emission;  // per glTF material: emissiveFactor * emissiveStrength
    std::vector<bool> m_doubleSided;
    std::vector<bool> m_cutOut;        // per glTF material: alpha below its cutoff everywhere
    std::vector<bool> m_normalMapped;  // per glTF material: has a normalTexture
    size_t m_degenerate = 0, m_nonTriangles = 0, m_noPositions = 0, m_badNormals = 0, m_cutOutPrimitives = 0;
    size_t m_badTangents = 0;
    size_t m_blendMaterials = 0, m_emissiveMasked = 0;  // alphaMode notes, one line each
    bool m_orthographicSeen = false;
};

AccessorView Importer::view(int index, const std::string& usedAt, int expectedType) {
    if (index < 0 || size_t(index) >= m_model.accessors.size())
        fail(usedAt, "accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor& a = m_model.accessors[index];
    std::string path = at("accessors", index);
    if (a.sparse.isSparse) fail(path, "sparse accessors are not supported");
    if (a.type != expectedType) fail(path, "unexpected accessor type for " + usedAt);
    AccessorView v;
    v.componentType = a.componentType;
    v.componentSize = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    v.components = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    if (v.componentSize <= 0 || v.components <= 0) fail(path, "unknown componentType or type");
    v.normalized = a.normalized;
    v.count = a.count;
    if (a.bufferView < 0) {
        // All zeros, and no buffer bounds its count: cap it so a corrupt count cannot
        // allocate without limit.
        if (v.count > (size_t(1) << 24)) fail(path + ".count", "too large for an accessor without bufferView");
        return v;
    }
    if (size_t(a.bufferView) >= m_model.bufferViews.size())
        fail(path + ".bufferView", "bufferView " + std::to_string(a.bufferView) + " does not exist");
    const tinygltf::BufferView& bv = m_model.bufferViews[a.bufferView];
    std::string bvPath = at("bufferViews", a.bufferView);
    if (bv.buffer < 0 || size_t(bv.buffer) >= m_model.buffers.size())
        fail(bvPath + ".buffer", "buffer " + std::to_string(bv.buffer) + " does not exist");
    const std::vector<unsigned char>& data = m_model.buffers[bv.buffer].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
        fail(bvPath, "byte range " + std::to_string(bv.byteOffset) + "+" + std::to_string(bv.byteLength) +
                         " exceeds its buffer (" + std::to_string(data.size()) + " bytes)");
    size_t element = size_t(v.componentSize) * v.components;
    v.stride = bv.byteStride ? bv.byteStride : element;
    if (v.stride < element) fail(bvPath + ".byteStride", "smaller than one element of " + path);
    if (v.count > 0) {
        // Every element takes at least one byte, so count <= byteLength keeps the product
        // below in 64 bits; likewise stride <= byteLength when there are two elements or more.
        bool fits = a.byteOffset <= bv.byteLength && v.count <= bv.byteLength &&
                    (v.count == 1 || v.stride <= bv.byteLength) &&
                    a.byteOffset + (v.count - 1) * v.stride + element <= bv.byteLength;
        if (!fits) fail(path, "reads past the end of bufferView " + std::to_string(a.bufferView));
    }
    v.data = data.data() + bv.byteOffset + a.byteOffset;
    return v;
}

glm::dmat4 Importer::localTransform(const tinygltf::Node& node, const std::string& path) const {
    auto finite = [](const std::vector<double>& v) { return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }); };
    if (!finite(node.matrix) || !finite(node.translation) || !finite(node.rotation) || !finite(node.scale))
        fail(path, "non-finite transform");
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16) fail(path + ".matrix", "expected 16 numbers");
        return glm::make_mat4(node.matrix.data());  // column-major in glTF and glm alike
    }
    if (!node.translation.empty() && node.translation.size() != 3) fail(path + ".translation", "expected 3 numbers");
    if (!node.rotation.empty() && node.rotation.size() != 4) fail(path + ".rotation", "expected 4 numbers");
    if (!node.scale.empty() && node.scale.size() != 3) fail(path + ".scale", "expected 3 numbers");
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (!node.translation.empty()) t = glm::translate(t, glm::make_vec3(node.translation.data()));
    if (!node.scale.empty()) s = glm::scale(s, glm::make_vec3(node.scale.data()));
    if (!node.rotation.empty()) {
        // Unit quaternion (x, y, z, w) to a rotation matrix (Shoemake 1985), columns listed.
        glm::dvec4 q = glm::make_vec4(node.rotation.data());
        if (glm::length(q) == 0.0) fail(path + ".rotation", "zero quaternion");
        q = glm::normalize(q);
        double x = q.x, y = q.y, z = q.z, w = q.w;
        r[0] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0};
        r[1] = {2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0};
        r[2] = {2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0};
    }
    return t * r * s;  // glTF: M = T * R * S
}

// glTF requires the nodes to form disjoint strict trees: every child index valid, no node
// with two parents, and (then) every node reachable from a parentless node, else it sits on
// a cycle. Checking the whole array also catches cycles outside the rendered scene.
void Importer::checkHierarchy() const {
    const auto& nodes = m_model.nodes;
    std::vector<int> parent(nodes.size(), -1);
    for (size_t i = 0; i < nodes.size(); ++i) {
        for (size_t c = 0; c < nodes[i].children.size(); ++c) {
            int child = nodes[i].children[c];
            std::string path = at("nodes", i) + ".children[" + std::to_string(c) + "]";
            if (child < 0 || size_t(child) >= nodes.size()) fail(path, "node " + std::to_string(child) + " does not exist");
            if (size_t(child) == i) fail(path, "node cycle: node " + std::to_string(i) + " is its own child");
            if (parent[child] >= 0)
                fail(path, "node cycle or shared node: node " + std::to_string(child) + " already has parent " +
                               std::to_string(parent[child]));
            parent[child] = int(i);
        }
    }
    std::vector<char> reached(nodes.size(), 0);
    std::vector<size_t> stack;
    for (size_t i = 0; i < nodes.size(); ++i)
        if (parent[i] < 0) stack.push_back(i);
    while (!stack.empty()) {
        size_t n = stack.back();
        stack.pop_back();
        reached[n] = 1;
        for (int child : nodes[n].children) stack.push_back(size_t(child));
    }
    for (size_t i = 0; i < nodes.size(); ++i)
        if (!reached[i]) fail(at("nodes", i), "node cycle: node " + std::to_string(i) + " is its own ancestor");
}

// glTF's metallic-roughness factors as a `pbr` material (SCENE_FORMAT.md v2, "glTF input";
// glTF 2.0 section 3.9.2): baseColorFactor (default 1; alpha ignored), metallicFactor and
// roughnessFactor (both default 1, as glTF says). A base colour above 1 is clamped to 1 (as
// v1 did for the diffuse albedo); a factor outside [0, 1] or not finite is an error.
Material Importer::metallicRoughnessMaterial(const tinygltf::Material& mat, const std::string& path) const {
    const tinygltf::PbrMetallicRoughness& pbr = mat.pbrMetallicRoughness;
    const std::string where = path + ".pbrMetallicRoughness";
    glm::dvec3 base(1.0);
    if (!pbr.baseColorFactor.empty()) {
        if (pbr.baseColorFactor.size() != 4) fail(where + ".baseColorFactor", "expected 4 numbers");
        base = glm::make_vec3(pbr.baseColorFactor.data());
    }
    if (!(base.x >= 0 && base.y >= 0 && base.z >= 0) || !std::isfinite(base.x + base.y + base.z))
        fail(where + ".baseColorFactor", "negative or non-finite");
    auto factor = [&](double value, const char* key) {
        if (!(value >= 0.0 && value <= 1.0)) fail(where + "." + key, "must be in [0, 1]");
        return float(value);
    };
    Material m;
    m.type = MaterialType::Pbr;
    m.pbr.baseColor = glm::clamp(glm::vec3(base), 0.0f, 1.0f);
    m.pbr.metallic = factor(pbr.metallicFactor, "metallicFactor");
    m.pbr.roughness = factor(pbr.roughnessFactor, "roughnessFactor");
    return m;
}

// glTF 2.0 section 3.9.4, alphaMode: OPAQUE (the default) ignores alpha; MASK cuts out the
// points whose alpha, baseColorFactor.a x baseColorTexture.a, is below alphaCutoff (default
// 0.5). Penumbra renders BLEND as MASK with cutoff 0.5 (a note says so): it traces no
// partly transparent surfaces. A textured alpha becomes the material's Alpha texture (the
// base colour texture's channel 3, tested in the traversal: textures/alpha_mask.glsl); a
// constant one is opaque or, below the cutoff, cuts out the whole material, whose primitives
// are then left out (true). An emissive material stays opaque, with a note: its light samples
// could not see its holes, and its emission would be counted where no surface is.
bool Importer::readAlphaMode(const tinygltf::Material& mat, const std::string& path, bool emissive,
                             const std::optional<MaterialTexture>& baseColor, Material& m) {
    const std::string& mode = mat.alphaMode;
    if (mode.empty() || mode == "OPAQUE") return false;
    if (mode != "MASK" && mode != "BLEND") fail(path + ".alphaMode", "expected \"OPAQUE\", \"MASK\" or \"BLEND\"");
    double cutoff = 0.5;
    if (mode == "BLEND") {
        ++m_blendMaterials;
    } else {
        cutoff = mat.alphaCutoff;
        if (!(cutoff >= 0.0 && cutoff <= 1e20)) fail(path + ".alphaCutoff", "must be a finite number >= 0");
    }
    if (emissive) {
        ++m_emissiveMasked;
        return false;
    }
    double alpha = 1.0;
    if (mat.pbrMetallicRoughness.baseColorFactor.size() == 4) alpha = mat.pbrMetallicRoughness.baseColorFactor[3];
    if (!(alpha >= 0.0 && alpha <= 1.0))
        fail(path + ".pbrMetallicRoughness.baseColorFactor[3]", "alpha must be in [0, 1]");
    if (!baseColor) return alpha < cutoff;
    MaterialTexture test = *baseColor;
    test.slot = TextureSlot::Alpha;
    test.scale = glm::vec3(float(alpha), float(cutoff), 0.0f);
    test.channel = 3;
    m.textures.push_back(test);
    return false;
}

void Importer::loadMaterials() {
    m_textures.checkLimits();  // from the image headers, before any image is decoded
    for (size_t i = 0; i < m_model.materials.size(); ++i) {
        const tinygltf::Material& mat = m_model.materials[i];
        std::string path = at("materials", i);
        glm::dvec3 emission(0.0);
        if (!mat.emissiveFactor.empty()) {
            if (mat.emissiveFactor.size() != 3) fail(path + ".emissiveFactor", "expected 3 numbers");
            emission = glm::make_vec3(mat.emissiveFactor.data());
        }
        auto ext = mat.extensions.find("KHR_materials_emissive_strength");
        if (ext != mat.extensions.end() && ext->second.Has("emissiveStrength")) {
            const tinygltf::Value& strength = ext->second.Get("emissiveStrength");
            const std::string strengthPath = path + ".extensions.KHR_materials_emissive_strength.emissiveStrength";
            if (!strength.IsNumber()) fail(strengthPath, "expected a number");
            // Refused at its own path: folded into the emission, it was reported as emissiveFactor.
            const double value = strength.GetNumberAsDouble();
            if (!(value >= 0.0 && std::isfinite(value))) fail(strengthPath, "negative or non-finite strength");
            emission *= value;
        }
        auto bad = [](glm::dvec3 c) {
            return !(c.x >= 0 && c.y >= 0 && c.z >= 0) || !std::isfinite(c.x + c.y + c.z) ||
                   std::max({c.x, c.y, c.z}) > double(float(kMaxRadiometric));
        };
        if (bad(emission))
            fail(path + ".emissiveFactor", "negative, non-finite or above 1e20 emission (README: ranges)");
        Material m = metallicRoughnessMaterial(mat, path);
        m.name = m_label + ":" + (mat.name.empty() ? path : mat.name);
        // The textures of base colour, metallic and roughness, each with its factor as the scale.
        GltfMaterialTextures textures = m_textures.metallicRoughness(mat, path);
        for (const std::optional<MaterialTexture>* field :
             {&textures.baseColor, &textures.metallic, &textures.roughness})
            if (*field) m.textures.push_back(**field);
        // emissiveFactor x strength x emissiveTexture (glTF 2.0 section 3.9.5): the texture
        // scales the emission of the primitives that use the material, which without a
        // factor is 0 whatever the texture says.
        if (emission != glm::dvec3(0.0))
            if (auto texture = m_textures.emission(mat, path)) m.textures.push_back(*texture);
        // A normal map bends the shading normal in the tangent frame of the primitives that
        // use the material, which then carry tangents (addPrimitive).
        std::optional<MaterialTexture> normalMap = m_textures.normal(mat, path);
        if (normalMap) m.textures.push_back(*normalMap);
        m_normalMapped.push_back(normalMap.has_value());
        m_cutOut.push_back(readAlphaMode(mat, path, emission != glm::dvec3(0.0), textures.baseColor, m));
        m_result.materials.push_back(m);
        m_emission.push_back(glm::vec3(emission));
        m_doubleSided.push_back(mat.doubleSided);
    }
}

void Importer::addPrimitive(const tinygltf::Primitive& prim, const glm::dmat4& world, const std::string& path) {
    int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode > TINYGLTF_MODE_TRIANGLE_FAN) fail(path + ".mode", "unknown mode " + std::to_string(mode));
    if (mode < TINYGLTF_MODE_TRIANGLES) { ++m_nonTriangles; return; }
    if (prim.material >= 0 && size_t(prim.material) >= m_model.materials.size())
        fail(path + ".material", "material " + std::to_string(prim.material) + " does not exist");
    if (prim.material >= 0 && m_cutOut[size_t(prim.material)]) {
        ++m_cutOutPrimitives;  // alphaMode MASK with a constant alpha below its cutoff
        return;
    }
    auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) { ++m_noPositions; return; }

    Shape shape;
    shape.type = ShapeType::Mesh;
    AccessorView pos = view(position->second, path + ".attributes.POSITION", TINYGLTF_TYPE_VEC3);
    shape.positions.resize(pos.count);
    for (size_t i = 0; i < pos.count; ++i) {
        glm::dvec3 p = glm::dvec3(world * glm::dvec4(pos.vec3(i), 1.0));
        if (!std::isfinite(p.x + p.y + p.z) ||
            std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}) > kMaxCoordinate)
            fail(path + ".attributes.POSITION",
                 "vertex " + std::to_string(i) + " is not within [-1e8, 1e8] (README: ranges)");
        shape.positions[i] = glm::vec3(p);
    }
    if (auto normal = prim.attributes.find("NORMAL"); normal != prim.attributes.end()) {
        AccessorView nv = view(normal->second, path + ".attributes.NORMAL", TINYGLTF_TYPE_VEC3);
        if (nv.count != pos.count)
            fail(path + ".attributes.NORMAL", std::to_string(nv.count) + " normals for " + std::to_string(pos.count) + " positions");
        // Normals transform with the inverse transpose of the linear part.
        glm::dmat3 normalMatrix = glm::inverse(glm::transpose(glm::dmat3(world)));
        shape.normals.resize(nv.count);
        for (size_t i = 0; i < nv.count && !shape.normals.empty(); ++i) {
            glm::dvec3 n = normalMatrix * nv.vec3(i);
            double len = glm::length(n);
            if (!(len > 1e-30) || !std::isfinite(len)) { shape.normals.clear(); ++m_badNormals; break; }
            shape.normals[i] = glm::vec3(n / len);
        }
    }
    if (auto uv = prim.attributes.find("TEXCOORD_0"); uv != prim.attributes.end()) {
        // glTF's uv has v = 0 at the top of the image, as SCENE_FORMAT.md's textures do.
        AccessorView tv = view(uv->second, path + ".attributes.TEXCOORD_0", TINYGLTF_TYPE_VEC2);
        if (tv.count != pos.count)
            fail(path + ".attributes.TEXCOORD_0",
                 std::to_string(tv.count) + " uvs for " + std::to_string(pos.count) + " positions");
        shape.uvs.resize(tv.count);
        for (size_t i = 0; i < tv.count; ++i) {
            glm::dvec2 t(tv.get(i, 0), tv.get(i, 1));
            if (!std::isfinite(t.x + t.y) || std::max(std::fabs(t.x), std::fabs(t.y)) > 1e30)
                fail(path + ".attributes.TEXCOORD_0", "uv " + std::to_string(i) + " is not finite");
            shape.uvs[i] = glm::vec2(t);
        }
    }

    const bool normalMapped = prim.material >= 0 && m_normalMapped[size_t(prim.material)];
    if (auto tangent = prim.attributes.find("TANGENT"); normalMapped && tangent != prim.attributes.end())
        readTangents(tangent->second, pos.count, world, path + ".attributes.TANGENT", shape);

    std::vector<uint32_t> order;
    if (prim.indices >= 0) {
        AccessorView iv = view(prim.indices, path + ".indices", TINYGLTF_TYPE_SCALAR);
        if (iv.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && iv.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            iv.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            fail(path + ".indices", "indices must be unsigned byte, short or int");
        order.resize(iv.count);
        for (size_t i = 0; i < iv.count; ++i) {
            double index = iv.get(i, 0);
            if (index >= double(pos.count))
                fail(path + ".indices", "index " + std::to_string(uint64_t(index)) + " out of range (" +
                                            std::to_string(pos.count) + " vertices)");
            order[i] = uint32_t(index);
        }
    } else {
        if (pos.count > std::numeric_limits<uint32_t>::max()) fail(path, "too many vertices");
        order.resize(pos.count);
        for (size_t i = 0; i < order.size(); ++i) order[i] = uint32_t(i);
    }

    // Triangle lists as they are; strips and fans unrolled (glTF 2.0 §3.7.2.1 topology).
    std::vector<std::array<uint32_t, 3>> triangles;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (order.size() % 3 != 0)
            fail(path, std::to_string(order.size()) + " triangle list indices is not a multiple of 3");
        for (size_t i = 0; i + 2 < order.size(); i += 3) triangles.push_back({order[i], order[i + 1], order[i + 2]});
    } else {
        for (size_t i = 0; i + 2 < order.size(); ++i) {
            if (mode == TINYGLTF_MODE_TRIANGLE_FAN) triangles.push_back({order[0], order[i + 1], order[i + 2]});
            else if (i % 2 == 0) triangles.push_back({order[i], order[i + 1], order[i + 2]});
            else triangles.push_back({order[i + 1], order[i], order[i + 2]});
        }
    }
    // A mirroring transform turns counter-clockwise into clockwise: glTF says the sign of
    // the determinant decides the winding, so swap two corners to keep the front face.
    bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
    for (auto [a, b, c] : triangles) {
        if (mirrored) std::swap(b, c);
        const glm::vec3 &pa = shape.positions[a], &pb = shape.positions[b], &pc = shape.positions[c];
        float area = 0.5f * glm::length(glm::cross(pb - pa, pc - pa));
        if (!(area > 0.0f) || !std::isfinite(area)) { ++m_degenerate; continue; }
        shape.indices.insert(shape.indices.end(), {a, b, c});
    }
    if (shape.indices.empty()) return;
    if (normalMapped && shape.tangents.empty()) computeTangents(shape);  // MikkTSpace-like (tangents.h)
    if (prim.material >= 0) {
        shape.emission = m_emission[prim.material];
        shape.twoSided = m_doubleSided[prim.material] && shape.isEmitter();
    }
    m_result.shapes.push_back(std::move(shape));
    m_result.shapeMaterials.push_back(prim.material);
}

// glTF 2.0 section 3.7.2.1: TANGENT is VEC4 float, xyz a unit tangent, w = +-1 the
// bitangent's sign. The tangent is a surface direction, so it goes through the linear part
// of the node transform; a mirroring transform (negative determinant) also mirrors the
// frame, which flips w (B' = L B while cross(N', T') turns the other way). A file whose
// tangents are not finite or are zero is read as if it had none (computed, with a note).
void Importer::readTangents(int accessor, size_t count, const glm::dmat4& world, const std::string& path,
                            Shape& shape) {
    AccessorView tv = view(accessor, path, TINYGLTF_TYPE_VEC4);
    if (tv.count != count)
        fail(path, std::to_string(tv.count) + " tangents for " + std::to_string(count) + " positions");
    const glm::dmat3 linear(world);
    const double mirror = glm::determinant(linear) < 0.0 ? -1.0 : 1.0;
    shape.tangents.resize(tv.count);
    for (size_t i = 0; i < tv.count; ++i) {
        glm::dvec3 t = linear * glm::dvec3(tv.get(i, 0), tv.get(i, 1), tv.get(i, 2));
        double len = glm::length(t), w = tv.get(i, 3);
        if (!(len > 1e-30) || !std::isfinite(len) || !std::isfinite(w)) {
            shape.tangents.clear();
            ++m_badTangents;
            return;
        }
        shape.tangents[i] = glm::vec4(glm::vec3(t / len), float(w < 0.0 ? -mirror : mirror));
    }
}

void Importer::addLight(const tinygltf::Node& node, const glm::dmat4& world, const std::string& path) {
    auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end() || !ext->second.Has("light")) return;
    std::string extPath = path + ".extensions.KHR_lights_punctual.light";
    const tinygltf::Value& index = ext->second.Get("light");
    // An index is an integer: 0.5 is refused, not truncated to light 0.
    if (!index.IsNumber() || index.GetNumberAsDouble() != std::floor(index.GetNumberAsDouble()))
        fail(extPath, "expected an integer light index");
    if (index.GetNumberAsDouble() < 0 || index.GetNumberAsDouble() >= double(m_model.lights.size()))
        fail(extPath, "no such light in KHR_lights_punctual.lights");
    size_t li = size_t(index.GetNumberAsInt());
    const tinygltf::Light& src = m_model.lights[li];
    std::string lightPath = "extensions.KHR_lights_punctual.lights[" + std::to_string(li) + "]";
    glm::dvec3 color(1.0);
    if (!src.color.empty()) {
        if (src.color.size() != 3) fail(lightPath + ".color", "expected 3 numbers");
        color = glm::make_vec3(src.color.data());
    }
    glm::dvec3 value = color * src.intensity;
    if (!(value.x >= 0 && value.y >= 0 && value.z >= 0) || !std::isfinite(value.x + value.y + value.z) ||
        std::max({value.x, value.y, value.z}) > double(float(kMaxRadiometric)))
        fail(lightPath, "negative, non-finite or above 1e20 intensity (README: ranges)");
    Light light;
    if (src.type == "point") light = pointLight(world, path);
    else if (src.type == "spot") light = spotLight(src, world, path, lightPath);
    else if (src.type == "directional") light = directionalLight(world, path);
    else fail(lightPath + ".type", "unknown light type \"" + src.type + "\"");
    light.intensity = glm::vec3(value);  // point, spot: candela read as W/sr; directional: lux as W/m^2
    m_result.lights.push_back(light);
}

// A point light at the node's origin.
Light Importer::pointLight(const glm::dmat4& world, const std::string& path) {
    Light light;
    light.type = LightType::Point;
    glm::dvec3 p = glm::dvec3(world * glm::dvec4(0, 0, 0, 1));
    if (!std::isfinite(p.x + p.y + p.z) || std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}) > kMaxCoordinate)
        fail(path, "light position not within [-1e8, 1e8] (README: ranges)");
    light.position = glm::vec3(p);
    return light;
}

// A spot light at the node's origin shining down its local -Z; the cone angles are radians,
// 0 <= innerConeAngle < outerConeAngle <= pi/2 (KHR_lights_punctual; SCENE_FORMAT.md `spot`).
Light Importer::spotLight(const tinygltf::Light& src, const glm::dmat4& world, const std::string& path,
                          const std::string& lightPath) {
    Light light = pointLight(world, path);
    light.type = LightType::Spot;
    light.direction = lightAxis(world, path);
    double inner = src.spot.innerConeAngle, outer = src.spot.outerConeAngle;
    if (!(outer > 0.0 && outer <= 0.5 * std::numbers::pi))
        fail(lightPath + ".spot.outerConeAngle", "must be in (0, pi/2] radians");
    if (!(inner >= 0.0 && inner < outer))
        fail(lightPath + ".spot.innerConeAngle", "must be in [0, outerConeAngle) radians");
    light.cosInner = float(std::cos(inner));
    light.cosOuter = float(std::cos(outer));
    if (!(light.cosOuter < light.cosInner))
        fail(lightPath + ".spot", "innerConeAngle and outerConeAngle are too close to tell apart");
    return light;
}

// A directional light shining down the node's local -Z.
Light Importer::directionalLight(const glm::dmat4& world, const std::string& path) {
    Light light;
    light.type = LightType::Directional;
    light.direction = lightAxis(world, path);
    return light;
}

// The unit direction a glTF light points in: its node's local -Z in world space.
glm::vec3 Importer::lightAxis(const glm::dmat4& world, const std::string& path) {
    glm::dvec3 d = glm::dmat3(world) * glm::dvec3(0, 0, -1);
    if (!(glm::length(d) > 0.0)) fail(path, "transform collapses the light direction");
    return glm::vec3(glm::normalize(d));
}

void Importer::addCamera(const tinygltf::Node& node, const glm::dmat4& world, const std::string& path) {
    if (node.camera < 0 || m_result.camera) return;
    if (size_t(node.camera) >= m_model.cameras.size())
        fail(path + ".camera", "camera " + std::to_string(node.camera) + " does not exist");
    const tinygltf::Camera& cam = m_model.cameras[node.camera];
    if (cam.type != "perspective") {
        if (!m_orthographicSeen) note("orthographic camera ignored (only perspective cameras are used)");
        m_orthographicSeen = true;
        return;
    }
    double yfov = cam.perspective.yfov;
    const float fovY = float(glm::degrees(yfov));
    // Checked as the degrees the scene keeps too: a yfov a hair below pi (or above 0)
    // rounds to 180 (or 0) degrees in float, which would otherwise be refused under
    // camera.fov_y, a path this file does not have.
    if (!(yfov > 0.0 && yfov < std::numbers::pi) || !(fovY > 0.0f && fovY < 180.0f))
        fail(at("cameras", node.camera) + ".perspective.yfov", "must be in (0, pi) radians");
    // glTF cameras look down their local -Z with +Y up (glTF 2.0 §3.10.1).
    glm::dvec3 eye = glm::dvec3(world * glm::dvec4(0, 0, 0, 1));
    glm::dvec3 forward = glm::dmat3(world) * glm::dvec3(0, 0, -1);
    glm::dvec3 up = glm::dmat3(world) * glm::dvec3(0, 1, 0);
    if (!(glm::length(forward) > 0.0) || !(glm::length(up) > 0.0) || !std::isfinite(eye.x + eye.y + eye.z))
        fail(path, "camera transform is degenerate");
    Camera c;
    c.eye = glm::vec3(eye);
    c.target = glm::vec3(eye + glm::normalize(forward));
    c.up = glm::vec3(glm::normalize(up));
    c.fovY = fovY;
    m_result.camera = c;
}

GltfImport Importer::run() {
    checkHierarchy();
    loadMaterials();

    // The default scene, else the first, else (no scenes at all) every root node.
    std::vector<int> roots;
    if (!m_model.scenes.empty()) {
        size_t s = m_model.defaultScene >= 0 ? size_t(m_model.defaultScene) : 0;
        if (s >= m_model.scenes.size()) fail("scene", "scene " + std::to_string(s) + " does not exist");
        roots = m_model.scenes[s].nodes;
        for (int r : roots)
            if (r < 0 || size_t(r) >= m_model.nodes.size()) fail(at("scenes", s) + ".nodes", "node " + std::to_string(r) + " does not exist");
    } else {
        std::vector<char> isChild(m_model.nodes.size(), 0);
        for (const auto& n : m_model.nodes)
            for (int c : n.children) isChild[c] = 1;
        for (size_t i = 0; i < m_model.nodes.size(); ++i)
            if (!isChild[i]) roots.push_back(int(i));
    }

    // Depth first in document order, iteratively so that deep hierarchies cannot overflow
    // the stack. The hierarchy is a forest (checkHierarchy), but a scene may still list a
    // node twice or list a child as a root.
    std::vector<char> visited(m_model.nodes.size(), 0);
    std::vector<std::pair<int, glm::dmat4>> stack;
    for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.emplace_back(*r, glm::dmat4(1.0));
    while (!stack.empty()) {
        auto [index, parentWorld] = stack.back();
        stack.pop_back();
        std::string path = at("nodes", index);
        if (visited[index]) fail(path, "node cycle: node " + std::to_string(index) + " is reached twice from the scene's roots");
        visited[index] = 1;
        const tinygltf::Node& node = m_model.nodes[index];
        glm::dmat4 world = parentWorld * localTransform(node, path);
        if (node.mesh >= 0) {
            if (size_t(node.mesh) >= m_model.meshes.size()) fail(path + ".mesh", "mesh " + std::to_string(node.mesh) + " does not exist");
            const auto& prims = m_model.meshes[node.mesh].primitives;
            for (size_t p = 0; p < prims.size(); ++p)
                addPrimitive(prims[p], world, at("meshes", node.mesh) + ".primitives[" + std::to_string(p) + "]");
        }
        addLight(node, world, path);
        addCamera(node, world, path);
        for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.emplace_back(*c, world);
    }

    if (m_blendMaterials)
        note(std::to_string(m_blendMaterials) +
             " materials with alphaMode BLEND are rendered as MASK with alphaCutoff 0.5 (no partial transparency)");
    if (m_emissiveMasked)
        note(std::to_string(m_emissiveMasked) + " emissive materials are rendered opaque (their alphaMode is ignored)");
    if (m_cutOutPrimitives)
        note("skipped " + std::to_string(m_cutOutPrimitives) +
             " primitives whose material is cut out everywhere (alpha below alphaCutoff)");
    if (m_degenerate) note("skipped " + std::to_string(m_degenerate) + " degenerate (zero-area) triangles");
    if (m_nonTriangles) note("skipped " + std::to_string(m_nonTriangles) + " point/line primitives (only triangles are rendered)");
    if (m_noPositions) note("skipped " + std::to_string(m_noPositions) + " primitives without POSITION");
    if (m_badTangents)
        note(std::to_string(m_badTangents) + " primitives had zero or non-finite tangents; they are computed instead");
    if (m_badNormals) note(std::to_string(m_badNormals) + " primitives had zero or non-finite normals; they are shaded flat");
    return std::move(m_result);
}

}  // namespace

GltfImport importGltf(const fs::path& file, const std::string& label) {
    std::string bytes = readInputFile(file, label, kMaxModelFileBytes);
    // A .glb starts with the magic "glTF"; anything else is read as JSON (.gltf).
    bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    std::vector<std::string> ignoredExtensions =
        checkGltfDocument(binary ? glbJsonChunk(bytes, label) : std::string_view(bytes), label);

    tinygltf::TinyGLTF loader;
    // Images are kept undecoded here and decoded by gltf_textures.cpp when a material uses them.
    GltfImageBytes images;
    loader.SetImageLoader(keepGltfImageBytes, &images);
    GltfFileAccess access{file.parent_path(), {}, {}};
    loader.SetFsCallbacks(confinedFsCallbacks(access));
    tinygltf::Model model;
    std::string err, warn;
    std::string baseDir = file.parent_path().string();
    bool ok = false;
    try {
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        if (binary) ok = loader.LoadBinaryFromMemory(&model, &err, &warn, data, unsigned(bytes.size()), baseDir);
        else ok = loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), unsigned(bytes.size()), baseDir);
    } catch (const std::exception& e) {
        throwInputError(label, "", firstLine(e.what()));
    }
    // A refused or failed read is reported even where tinygltf only warns (images).
    if (!access.refused.empty())
        throwInputError(label, "",
                        "refusing to read \"" + elideUri(access.refused) +
                            "\": it is outside the model's folder (--allow-any-path reads it)");
    if (!access.failed.empty()) throwInputError(label, "", elideWords(access.failed));
    if (!ok) throwInputError(label, "", err.empty() ? "not a valid glTF file" : firstLine(err));
    GltfImport result = Importer(model, label, images).run();
    std::string note = ignoredGltfExtensionsNote(ignoredExtensions);
    if (!note.empty()) result.notes.push_back(label + ": " + note);
    return result;
}

}  // namespace penumbra
