// Material fields given as textures (SCENE_FORMAT.md "Textures (v2)"): reading
// {"texture": FILE, "scale": S}, loading each distinct (file, decoding) once into
// Scene::textures, and the limits on how many textures and texels a scene may hold.
// The JSON and glTF material readers call this; what a slot means is the GPU's (types.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <utility>

#include "image/image_file.h"
#include "scene/json_reader.h"
#include "scene/scene.h"

namespace penumbra {

// A scene holds at most kMaxTextures distinct textures of at most kMaxTextureTexels texels
// in all (each texel 8 bytes on the GPU, RGBA half floats: 1 GiB). 128M texels is 128
// textures of 1024 x 1024, or 512 of 512 x 512; the texel buffer they share stays within
// the 2^27-texel limit of lavapipe's texel buffers (two texels per buffer element).
inline constexpr size_t kMaxTextures = 4096;
inline constexpr uint64_t kMaxTextureTexels = uint64_t(1) << 27;

// The decoded image becomes a Texture: RGBA rounded to half floats (values beyond the
// largest half, 65504, are clamped to it; textured fields are clamped to [0, 1] anyway).
Texture makeTexture(std::string file, bool srgb, uint32_t width, uint32_t height, const float* rgba);

class TextureTable {
public:
    explicit TextureTable(std::vector<Texture>& textures) : m_textures(textures) {}

    // The index of the texture known by `key` (a resolved file name, or "model.glb#images[2]")
    // and decoding, calling `load` only the first time; fail(why) when a limit is passed.
    // `load` is given the check of the limits, to call with the image's size from its header
    // before it decodes any pixel (readImageFile's AcceptImageSize); its result is checked
    // again, for a load that had no header to read.
    uint32_t add(const std::string& key, bool srgb, const std::function<Texture(const AcceptImageSize&)>& load,
                 const std::function<void(const std::string&)>& fail);

private:
    std::vector<Texture>& m_textures;
    std::map<std::pair<std::string, bool>, uint32_t> m_index;
    uint64_t m_texels = 0;
};

// Reads texture objects in a scene file's materials. Files are relative to `baseDir` and,
// unless any path is allowed (input_file.h), must lie inside it.
class MaterialTextureReader {
public:
    MaterialTextureReader(Scene& scene, std::filesystem::path baseDir)
        : m_table(scene.textures), m_baseDir(std::move(baseDir)) {}

    // Whether `field` is written as a texture object (else it is a plain value).
    static bool isTexture(const JsonReader& field) { return field.json().is_object(); }

    // A colour field in [0, 1] (albedo, kd, ks, base_color): {"texture", "scale"} with scale
    // a colour in [0, 1] (default 1), the texture sRGB-decoded. Adds the MaterialTexture to
    // `material` and returns the scale, the field's value where the texture reads 1.
    glm::vec3 colorField(const JsonReader& field, TextureSlot slot, Material& material);
    // A number field in [0, 1] (metallic, roughness): scale a number in [0, 1], channel
    // `channel` of the texture read linearly (number data is never sRGB-encoded).
    float numberField(const JsonReader& field, TextureSlot slot, uint32_t channel, Material& material);

    TextureTable& table() { return m_table; }

private:
    uint32_t loadFile(const JsonReader& fileField, bool srgb);

    TextureTable m_table;
    std::filesystem::path m_baseDir;
};

}  // namespace penumbra
