// KHR_texture_transform -> UvTransform (see gltf_texture_transform.h).
#include "scene/gltf_texture_transform.h"

#include <cmath>

#include "core/errors.h"
#include "scene/limits.h"

namespace penumbra {
namespace {

// One number of the extension, finite and no larger than kMaxCoordinate in magnitude (a
// larger offset or scale leaves no float precision in the coordinates it produces).
double number(const tinygltf::Value& value, const std::string& label, const std::string& path) {
    if (!value.IsNumber()) throwInputError(label, path, "expected a number");
    const double x = value.GetNumberAsDouble();
    if (!(std::fabs(x) <= kMaxCoordinate)) throwInputError(label, path, "must be finite and at most 1e8 in magnitude");
    return x;
}

// A two-number array (offset, scale), or `fallback` when the key is absent.
glm::dvec2 pair(const tinygltf::Value& ext, const char* key, glm::dvec2 fallback, const std::string& label,
                const std::string& path) {
    if (!ext.Has(key)) return fallback;
    const tinygltf::Value& value = ext.Get(key);
    const std::string at = path + "." + key;
    if (!value.IsArray() || value.ArrayLen() != 2) throwInputError(label, at, "expected 2 numbers");
    return {number(value.Get(0), label, at + "[0]"), number(value.Get(1), label, at + "[1]")};
}

}  // namespace

GltfTextureTransform readTextureTransform(const tinygltf::ExtensionMap& extensions, int texCoord,
                                          const std::string& label, const std::string& path) {
    GltfTextureTransform out;
    out.texCoord = texCoord;
    auto found = extensions.find("KHR_texture_transform");
    if (found == extensions.end()) return out;
    const tinygltf::Value& ext = found->second;
    const std::string where = path + ".extensions.KHR_texture_transform";
    if (!ext.IsObject()) throwInputError(label, where, "expected an object");
    const glm::dvec2 offset = pair(ext, "offset", glm::dvec2(0.0), label, where);
    const glm::dvec2 scale = pair(ext, "scale", glm::dvec2(1.0), label, where);
    const double rotation = ext.Has("rotation") ? number(ext.Get("rotation"), label, where + ".rotation") : 0.0;
    if (ext.Has("texCoord")) {
        const tinygltf::Value& set = ext.Get("texCoord");
        if (!set.IsInt() || set.GetNumberAsInt() < 0)
            throwInputError(label, where + ".texCoord", "expected a non-negative integer");
        out.texCoord = set.GetNumberAsInt();
    }
    // The extension's T(offset) R(rotation) S(scale), with the rotation counter-clockwise in
    // glTF's u-right, v-down uv space:
    //   u' = cos sx u + sin sy v + ox,   v' = -sin sx u + cos sy v + oy.
    // The GLSL listing in the extension's README reads as the opposite rotation when its mat3
    // is taken column-major; KhronosGroup/glTF issue 1563 says so, and the TextureTransformTest
    // sample (its "Correct" marker), Blender and Babylon rotate as here.
    // Without rotation the rows hold exactly the file's numbers (sin 0 = 0, cos 0 = 1).
    const double c = std::cos(rotation), s = std::sin(rotation);
    out.uv.u = glm::vec3(glm::dvec3(c * scale.x, s * scale.y, offset.x));
    out.uv.v = glm::vec3(glm::dvec3(-s * scale.x, c * scale.y, offset.y));
    return out;
}

GltfTextureTransform readTextureTransform(const tinygltf::TextureInfo& info, const std::string& label,
                                          const std::string& path) {
    return readTextureTransform(info.extensions, info.texCoord, label, path);
}

}  // namespace penumbra
