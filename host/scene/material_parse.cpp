// The material kinds of SCENE_FORMAT.md, parsed one function each: keys, defaults and
// ranges (see material_parse.h). What each BRDF computes is its shader's
// (shaders/bsdf/<kind>.glsl); how it is packed for the GPU is render/material_arrays.cpp's.
#include "scene/material_parse.h"

namespace penumbra {
namespace {

// The fields of one material being read. A field written as a texture object stands for
// its scale here, the value where the texture reads 1 (material_textures.h).
struct Fields {
    const JsonReader& m;
    MaterialTextureReader& textures;
    Material& mat;

    // A colour whose components are reflectances: each in [0, 1].
    glm::vec3 unitColor(const char* key, glm::vec3 fallback, TextureSlot slot) const {
        if (m.has(key) && MaterialTextureReader::isTexture(m.at(key))) return textures.colorField(m.at(key), slot, mat);
        glm::vec3 c = m.colorOr(key, fallback);
        if (c.x > 1.0f || c.y > 1.0f || c.z > 1.0f) m.at(key).fail("components must be in [0, 1]");
        return c;
    }

    // A factor in [0, 1] (glTF's metallic and roughness); a texture's first channel.
    float unitNumber(const char* key, float fallback, TextureSlot slot) const {
        if (m.has(key) && MaterialTextureReader::isTexture(m.at(key)))
            return textures.numberField(m.at(key), slot, 0, mat);
        float x = m.numberOr(key, fallback);
        if (x < 0.0f || x > 1.0f) m.at(key).fail("must be in [0, 1]");
        return x;
    }
};

void parseDiffuse(const Fields& f) {
    f.m.expectKeys({"type", "albedo"}, "a diffuse material");
    f.mat.type = MaterialType::Diffuse;
    f.mat.kd = f.unitColor("albedo", glm::vec3(0.8f), TextureSlot::Kd);
}

void parsePhong(const Fields& f) {
    const JsonReader& m = f.m;
    Material& mat = f.mat;
    m.expectKeys({"type", "kd", "ks", "exponent"}, "a phong material");
    mat.type = MaterialType::Phong;
    mat.kd = f.unitColor("kd", glm::vec3(0.5f), TextureSlot::Kd);
    mat.ks = f.unitColor("ks", glm::vec3(0.5f), TextureSlot::Ks);
    mat.exponent = m.numberOr("exponent", 20.0f);
    if (mat.exponent < 0.0f) m.at("exponent").fail("must be >= 0");
    // kd + ks <= 1 keeps the normalized Phong BRDF from reflecting more than it
    // receives (Lafortune & Willems 1994); a small tolerance absorbs decimal rounding.
    // Textured fields are checked by their scales (textures/textures.glsl keeps kd + ks <= 1
    // where a texture would pass it).
    for (int c = 0; c < 3; ++c)
        if (mat.kd[c] + mat.ks[c] > 1.0f + 1e-6f)
            m.fail("kd + ks exceeds 1 in the " +
                   std::string(c == 0   ? "red"
                               : c == 1 ? "green"
                                        : "blue") +
                   " channel (" + std::to_string(mat.kd[c]) + " + " + std::to_string(mat.ks[c]) + ")");
}

// The slots (shaders/shared/types.h) are those of pbr's GPU packing: kd = base_color,
// ks.x = metallic, ks.y = roughness.
void parsePbr(const Fields& f) {
    f.m.expectKeys({"type", "base_color", "metallic", "roughness"}, "a pbr material");
    f.mat.type = MaterialType::Pbr;
    f.mat.pbr.baseColor = f.unitColor("base_color", glm::vec3(0.8f), TextureSlot::Kd);
    f.mat.pbr.metallic = f.unitNumber("metallic", 0.0f, TextureSlot::KsX);
    f.mat.pbr.roughness = f.unitNumber("roughness", 0.5f, TextureSlot::KsY);
}

}  // namespace

Material parseMaterial(const JsonReader& m, const std::string& name, MaterialTextureReader& textures) {
    std::string type = m.has("type") ? m.at("type").choice({"diffuse", "phong", "pbr"}) : "diffuse";
    Material mat{name};
    const Fields fields{m, textures, mat};
    if (type == "diffuse") parseDiffuse(fields);
    else if (type == "phong") parsePhong(fields);
    else parsePbr(fields);
    return mat;
}

}  // namespace penumbra
