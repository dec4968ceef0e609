// Internal to host/scene: the textures of glTF materials (glTF 2.0 section 3.9, "Materials";
// 5.26-5.29 images, samplers, textures): baseColorTexture and metallicRoughnessTexture
// read through TEXCOORD_0 (after KHR_texture_transform, gltf_texture_transform.h), from GLB buffer views, data URIs or external files, decoded by
// image/image_file.h into GltfImport::textures. The material function (load_gltf.cpp)
// decides which fields they fill.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "scene/scene.h"

namespace penumbra {

// The bytes of images given by URI (data URIs and external files), by image index: what
// tinygltf hands to its image callback. Images in buffer views are read from the model.
struct GltfImageBytes {
    std::map<int, std::string> byIndex;
};

// A tinygltf image callback that keeps the undecoded bytes in a GltfImageBytes (user data).
bool keepGltfImageBytes(tinygltf::Image* image, int index, std::string* err, std::string* warn, int, int,
                        const unsigned char* bytes, int size, void* userData);

// The textured fields of one glTF material, each with its factor as the scale
// (SCENE_FORMAT.md "glTF input" v2): base colour (sRGB, slot Kd), metallic (blue channel
// of metallicRoughnessTexture, linear, slot KsX) and roughness (its green channel, slot KsY).
struct GltfMaterialTextures {
    std::optional<MaterialTexture> baseColor, metallic, roughness;
};

class GltfTextureReader {
public:
    GltfTextureReader(const tinygltf::Model& model, std::string label, const GltfImageBytes& bytes,
                      std::vector<Texture>& textures, std::vector<std::string>& notes)
        : m_model(model), m_label(std::move(label)), m_bytes(bytes), m_textures(textures), m_notes(notes) {}

    // Refuses the model, naming the first image past a limit, when the images its materials
    // use (each distinct (bytes, decoding) once) would exceed the scene's texture limits
    // (material_textures.h), by their sizes from their headers: before any is decoded.
    void checkLimits();

    // The base colour texture alone (decoded only when present): what a diffuse material uses.
    std::optional<MaterialTexture> baseColor(const tinygltf::Material& material, const std::string& path);
    // All three fields, for a material that has them all (metallic-roughness).
    GltfMaterialTextures metallicRoughness(const tinygltf::Material& material, const std::string& path);
    // The emissive texture (sRGB, slot Emission, scale 1: emissiveFactor stays in the
    // shape's emission), decoded only when present; the caller asks only for emitters.
    std::optional<MaterialTexture> emission(const tinygltf::Material& material, const std::string& path);
    // The tangent-space normal map (linear data, slot Normal, scale.x the normalTexture's
    // finite scale), decoded only when present.
    std::optional<MaterialTexture> normal(const tinygltf::Material& material, const std::string& path);

private:
    // Index into m_textures of glTF texture `info` decoded as sRGB colour or linear data,
    // its sampler's wrapping along u and v, and its KHR_texture_transform (identity without); throws InputError naming the glTF path.
    uint32_t texture(const tinygltf::TextureInfo& info, const std::string& path, bool srgb,
                     std::pair<TextureWrap, TextureWrap>& wrap, UvTransform& uv);
    TextureWrap wrapMode(int glWrap, const std::string& path) const;
    std::string imageBytes(int index, const std::string& path) const;
    void noteOnce(const std::string& text);

    const tinygltf::Model& m_model;
    std::string m_label;
    const GltfImageBytes& m_bytes;
    std::vector<Texture>& m_textures;
    std::vector<std::string>& m_notes;
    // (image bytes, sRGB) -> texture: images that hold the same bytes (one file named by
    // several images) are decoded once.
    std::map<std::pair<std::string, bool>, uint32_t> m_decoded;
    std::vector<std::string> m_noted;
};

}  // namespace penumbra
