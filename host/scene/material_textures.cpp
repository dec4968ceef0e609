// Texture objects of material fields, the scene's texture table and its limits (see
// material_textures.h).
#include "scene/material_textures.h"

#include <algorithm>

#include <glm/gtc/packing.hpp>

#include "core/errors.h"
#include "image/image_file.h"
#include "scene/scene_input_file.h"

namespace penumbra {

namespace fs = std::filesystem;

Texture makeTexture(std::string file, bool srgb, uint32_t width, uint32_t height, const float* rgba) {
    Texture t;
    t.file = std::move(file);
    t.srgb = srgb;
    t.width = width;
    t.height = height;
    const size_t count = size_t(width) * height * 4;
    t.texels.resize(count);
    constexpr float kMaxHalf = 65504.0f;
    for (size_t i = 0; i < count; ++i) t.texels[i] = glm::packHalf1x16(std::clamp(rgba[i], -kMaxHalf, kMaxHalf));
    return t;
}

uint32_t TextureTable::add(const std::string& key, bool srgb,
                           const std::function<Texture(const AcceptImageSize&)>& load,
                           const std::function<void(const std::string&)>& fail) {
    auto found = m_index.find({key, srgb});
    if (found != m_index.end()) return found->second;
    if (m_textures.size() >= kMaxTextures)
        fail("more than " + std::to_string(kMaxTextures) + " distinct textures in the scene (README: texture limits)");
    auto withinLimits = [&](uint32_t width, uint32_t height) {
        if (m_texels + uint64_t(width) * height > kMaxTextureTexels)
            fail("the scene's textures exceed " + std::to_string(kMaxTextureTexels) +
                 " texels in all (README: texture limits)");
    };
    Texture texture = load(withinLimits);
    withinLimits(texture.width, texture.height);
    m_texels += uint64_t(texture.width) * texture.height;
    uint32_t index = uint32_t(m_textures.size());
    m_textures.push_back(std::move(texture));
    m_index[{key, srgb}] = index;
    return index;
}

uint32_t MaterialTextureReader::loadFile(const JsonReader& fileField, bool srgb) {
    fs::path file = sceneRelativeInputFile(fileField, m_baseDir);
    std::error_code ec;
    fs::path resolved = fs::weakly_canonical(file, ec);
    std::string key = ec ? file.string() : resolved.string();
    auto load = [&](const AcceptImageSize& withinLimits) {
        bool overLimits = false;  // the table's refusal, already worded: passed on as it is
        auto accept = [&](uint32_t width, uint32_t height) {
            overLimits = true;
            withinLimits(width, height);
            overLimits = false;
        };
        try {
            ImageFile image = readImageFile(file, file.string(), srgb ? ColorDecode::Srgb : ColorDecode::Linear,
                                            kMaxImagePixels, accept);
            return makeTexture(file.string(), srgb, image.width, image.height, image.rgba.data());
        } catch (const InputError& e) {
            if (overLimits) throw;
            fileField.fail(e.what());  // "scene.json: materials.m.albedo.texture: FILE: why"
        }
    };
    return m_table.add(key, srgb, load, [&](const std::string& why) { fileField.fail(why); });
}

glm::vec3 MaterialTextureReader::colorField(const JsonReader& field, TextureSlot slot, Material& material) {
    field.expectKeys({"texture", "scale"}, "a texture");
    glm::vec3 scale(1.0f);
    if (auto s = field.find("scale")) {
        scale = s->color();  // non-negative, finite; a single number is grey
        if (std::max({scale.x, scale.y, scale.z}) > 1.0f) s->fail("components must be in [0, 1]");
    }
    uint32_t texture = loadFile(field.at("texture"), true);
    material.textures.push_back({slot, texture, scale, 0});
    return scale;
}

float MaterialTextureReader::numberField(const JsonReader& field, TextureSlot slot, uint32_t channel,
                                         Material& material) {
    field.expectKeys({"texture", "scale"}, "a texture");
    float scale = 1.0f;
    if (auto s = field.find("scale")) {
        scale = s->number();
        if (!(scale >= 0.0f && scale <= 1.0f)) s->fail("must be in [0, 1]");
    }
    uint32_t texture = loadFile(field.at("texture"), false);
    material.textures.push_back({slot, texture, glm::vec3(scale), channel});
    return scale;
}

}  // namespace penumbra
