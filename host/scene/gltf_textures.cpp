// glTF material textures: image bytes from URIs (kept by the image callback) or buffer
// views (bounds-checked here), their sizes checked against the limits from the headers,
// decoded once per (bytes, decoding), and the sampler's wrap modes (see gltf_textures.h).
#include "scene/gltf_textures.h"

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "image/image_file.h"
#include "scene/gltf_texture_transform.h"
#include "scene/material_textures.h"

namespace penumbra {
namespace {

std::string at(const char* array, size_t index) { return std::string(array) + "[" + std::to_string(index) + "]"; }

// Factors are clamped into [0, 1] like the plain values of load_gltf.cpp (the scale of a
// colour or number field, SCENE_FORMAT.md "Textures (v2)").
float unit(double x) { return float(std::clamp(x, 0.0, 1.0)); }

}  // namespace

bool keepGltfImageBytes(tinygltf::Image* image, int index, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void* userData) {
    // Buffer-view images are read from the model instead, with their range checked.
    if (image->bufferView >= 0 || size <= 0) return true;
    static_cast<GltfImageBytes*>(userData)->byIndex[index].assign(reinterpret_cast<const char*>(bytes), size_t(size));
    return true;
}

void GltfTextureReader::noteOnce(const std::string& text) {
    if (std::find(m_noted.begin(), m_noted.end(), text) != m_noted.end()) return;
    m_noted.push_back(text);
    m_notes.push_back(m_label + ": " + text);
}

std::string GltfTextureReader::imageBytes(int index, const std::string& path) const {
    const tinygltf::Image& image = m_model.images[size_t(index)];
    if (image.bufferView < 0) {
        auto found = m_bytes.byIndex.find(index);
        // tinygltf only warns when an external image cannot be read.
        if (found == m_bytes.byIndex.end())
            throwInputError(m_label, path,
                            image.uri.empty() ? "image has no data"
                                              : "cannot read \"" + elideUri(image.uri) + "\" (missing or unreadable)");
        return found->second;
    }
    if (size_t(image.bufferView) >= m_model.bufferViews.size())
        throwInputError(m_label, path + ".bufferView",
                        "bufferView " + std::to_string(image.bufferView) + " does not exist");
    const tinygltf::BufferView& bv = m_model.bufferViews[size_t(image.bufferView)];
    std::string bvPath = at("bufferViews", size_t(image.bufferView));
    if (bv.buffer < 0 || size_t(bv.buffer) >= m_model.buffers.size())
        throwInputError(m_label, bvPath + ".buffer", "buffer " + std::to_string(bv.buffer) + " does not exist");
    const std::vector<unsigned char>& data = m_model.buffers[size_t(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
        throwInputError(m_label, bvPath, "byte range exceeds its buffer (" + std::to_string(data.size()) + " bytes)");
    return std::string(reinterpret_cast<const char*>(data.data()) + bv.byteOffset, bv.byteLength);
}

TextureWrap GltfTextureReader::wrapMode(int glWrap, const std::string& path) const {
    switch (glWrap) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT: return TextureWrap::Repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TextureWrap::Clamp;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TextureWrap::Mirror;
        default: throwInputError(m_label, path, "unknown wrap mode " + std::to_string(glWrap));
    }
}

uint32_t GltfTextureReader::texture(const tinygltf::TextureInfo& info, const std::string& path, bool srgb,
                                    std::pair<TextureWrap, TextureWrap>& wrap, UvTransform& uv) {
    if (info.index < 0 || size_t(info.index) >= m_model.textures.size())
        throwInputError(m_label, path + ".index", "texture " + std::to_string(info.index) + " does not exist");
    const GltfTextureTransform transform = readTextureTransform(info, m_label, path);
    uv = transform.uv;
    // SCENE_FORMAT.md: TEXCOORD_0. Another set (the textureInfo's, or KHR_texture_transform's
    // override) is read as set 0, with a note.
    if (transform.texCoord != 0)
        noteOnce("textures using TEXCOORD_" + std::to_string(transform.texCoord) + " are read with TEXCOORD_0");
    const tinygltf::Texture& tex = m_model.textures[size_t(info.index)];
    std::string texPath = at("textures", size_t(info.index));
    if (tex.source < 0 || size_t(tex.source) >= m_model.images.size())
        throwInputError(m_label, texPath + ".source",
                        tex.source < 0 ? "texture has no source image (only PNG and JPEG sources are read)"
                                       : "image " + std::to_string(tex.source) + " does not exist");
    wrap = {TextureWrap::Repeat, TextureWrap::Repeat};  // glTF's default without a sampler
    if (tex.sampler >= 0) {
        if (size_t(tex.sampler) >= m_model.samplers.size())
            throwInputError(m_label, texPath + ".sampler",
                            "sampler " + std::to_string(tex.sampler) + " does not exist");
        const tinygltf::Sampler& s = m_model.samplers[size_t(tex.sampler)];
        std::string samplerPath = at("samplers", size_t(tex.sampler));
        wrap = {wrapMode(s.wrapS, samplerPath + ".wrapS"), wrapMode(s.wrapT, samplerPath + ".wrapT")};
    }
    std::string imagePath = at("images", size_t(tex.source));
    std::pair<std::string, bool> key{imageBytes(tex.source, imagePath), srgb};
    auto found = m_decoded.find(key);
    if (found != m_decoded.end()) return found->second;
    ImageFile image =
        decodeImage(key.first, m_label + ": " + imagePath, srgb ? ColorDecode::Srgb : ColorDecode::Linear);
    uint32_t index = uint32_t(m_textures.size());
    m_textures.push_back(makeTexture(m_label + "#" + imagePath, srgb, image.width, image.height, image.rgba.data()));
    m_decoded[std::move(key)] = index;
    return index;
}

// normalTexture's own textureInfo type, as the textureInfo the readers take (same index,
// texCoord and extensions: KHR_texture_transform applies to it as to any other).
static tinygltf::TextureInfo asTextureInfo(const tinygltf::NormalTextureInfo& normal) {
    tinygltf::TextureInfo info;
    info.index = normal.index;
    info.texCoord = normal.texCoord;
    info.extensions = normal.extensions;
    return info;
}

void GltfTextureReader::checkLimits() {
    std::map<std::pair<std::string, bool>, uint64_t> used;  // (bytes, sRGB) -> texels
    uint64_t texels = 0;
    auto count = [&](const tinygltf::TextureInfo& info, bool srgb) {
        // A reference that does not resolve is reported by texture(), at the material's path.
        if (info.index < 0 || size_t(info.index) >= m_model.textures.size()) return;
        const int source = m_model.textures[size_t(info.index)].source;
        if (source < 0 || size_t(source) >= m_model.images.size()) return;
        std::string imagePath = at("images", size_t(source));
        std::pair<std::string, bool> key{imageBytes(source, imagePath), srgb};
        if (used.count(key)) return;
        auto [width, height] = imageSize(key.first, m_label + ": " + imagePath);
        texels += uint64_t(width) * height;
        used.emplace(std::move(key), uint64_t(width) * height);
        if (used.size() > kMaxTextures)
            throwInputError(m_label, imagePath,
                            "more than " + std::to_string(kMaxTextures) +
                                " distinct textures in the model (README: texture limits)");
        if (texels > kMaxTextureTexels)
            throwInputError(m_label, imagePath,
                            "the model's textures exceed " + std::to_string(kMaxTextureTexels) +
                                " texels in all (README: texture limits)");
    };
    // The textures metallicRoughness() and emission() read, with the same decodings.
    for (const tinygltf::Material& material : m_model.materials) {
        count(material.pbrMetallicRoughness.baseColorTexture, true);
        count(material.pbrMetallicRoughness.metallicRoughnessTexture, false);
        count(material.emissiveTexture, true);
        count(asTextureInfo(material.normalTexture), false);
    }
}

std::optional<MaterialTexture> GltfTextureReader::baseColor(const tinygltf::Material& material,
                                                            const std::string& path) {
    const tinygltf::PbrMetallicRoughness& pbr = material.pbrMetallicRoughness;
    if (pbr.baseColorTexture.index < 0) return std::nullopt;
    glm::vec3 factor(1.0f);
    if (pbr.baseColorFactor.size() == 4)
        factor = {unit(pbr.baseColorFactor[0]), unit(pbr.baseColorFactor[1]), unit(pbr.baseColorFactor[2])};
    std::pair<TextureWrap, TextureWrap> wrap;
    UvTransform uv;
    uint32_t t = texture(pbr.baseColorTexture, path + ".pbrMetallicRoughness.baseColorTexture", true, wrap, uv);
    return MaterialTexture{TextureSlot::Kd, t, factor, 0, wrap.first, wrap.second, uv};
}

GltfMaterialTextures GltfTextureReader::metallicRoughness(const tinygltf::Material& material, const std::string& path) {
    GltfMaterialTextures out;
    out.baseColor = baseColor(material, path);
    const tinygltf::PbrMetallicRoughness& pbr = material.pbrMetallicRoughness;
    if (pbr.metallicRoughnessTexture.index >= 0) {
        // glTF 2.0 section 3.9.2: metalness in the blue channel, roughness in green; linear data.
        std::pair<TextureWrap, TextureWrap> wrap;
        UvTransform uv;
        uint32_t t = texture(pbr.metallicRoughnessTexture, path + ".pbrMetallicRoughness.metallicRoughnessTexture",
                             false, wrap, uv);
        out.metallic =
            MaterialTexture{TextureSlot::KsX, t, glm::vec3(unit(pbr.metallicFactor)), 2, wrap.first, wrap.second, uv};
        out.roughness =
            MaterialTexture{TextureSlot::KsY, t, glm::vec3(unit(pbr.roughnessFactor)), 1, wrap.first, wrap.second, uv};
    }
    return out;
}

std::optional<MaterialTexture> GltfTextureReader::emission(const tinygltf::Material& material,
                                                           const std::string& path) {
    if (material.emissiveTexture.index < 0) return std::nullopt;
    // glTF 2.0 section 3.9.5: emissiveTexture is sRGB colour; the emitted radiance is
    // emissiveFactor (times emissive_strength) times it, and the factor stays in the Light.
    std::pair<TextureWrap, TextureWrap> wrap;
    UvTransform uv;
    uint32_t t = texture(material.emissiveTexture, path + ".emissiveTexture", true, wrap, uv);
    return MaterialTexture{TextureSlot::Emission, t, glm::vec3(1.0f), 0, wrap.first, wrap.second, uv};
}

std::optional<MaterialTexture> GltfTextureReader::normal(const tinygltf::Material& material, const std::string& path) {
    const tinygltf::NormalTextureInfo& info = material.normalTexture;
    if (info.index < 0) return std::nullopt;
    // glTF 2.0 section 3.9.3: linear RGB, n = normalize((2 rgb - 1) (scale, scale, 1)) in the
    // tangent frame (textures/normal_map.glsl decodes it).
    if (!std::isfinite(info.scale) || std::fabs(info.scale) > 1e8)
        throwInputError(m_label, path + ".normalTexture.scale", "must be a finite number");
    std::pair<TextureWrap, TextureWrap> wrap;
    UvTransform uv;
    uint32_t t = texture(asTextureInfo(info), path + ".normalTexture", false, wrap, uv);
    return MaterialTexture{TextureSlot::Normal, t, glm::vec3(float(info.scale), 0.0f, 0.0f), 0, wrap.first,
                           wrap.second,         uv};
}

}  // namespace penumbra
