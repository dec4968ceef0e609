// The material kinds of SCENE_FORMAT.md, parsed one function each: keys, defaults and
// ranges (see material_parse.h). What each BRDF computes is its shader's
// (shaders/bsdf/<kind>.glsl); how it is packed for the GPU is render/material_arrays.cpp's.
#include "scene/material_parse.h"

namespace penumbra {
namespace {

// A colour whose components are reflectances: each in [0, 1].
glm::vec3 unitColor(const JsonReader& m, const char* key, glm::vec3 fallback) {
    glm::vec3 c = m.colorOr(key, fallback);
    if (c.x > 1.0f || c.y > 1.0f || c.z > 1.0f) m.at(key).fail("components must be in [0, 1]");
    return c;
}

void parseDiffuse(const JsonReader& m, Material& mat) {
    m.expectKeys({"type", "albedo"}, "a diffuse material");
    mat.type = MaterialType::Diffuse;
    mat.kd = unitColor(m, "albedo", glm::vec3(0.8f));
}

void parsePhong(const JsonReader& m, Material& mat) {
    m.expectKeys({"type", "kd", "ks", "exponent"}, "a phong material");
    mat.type = MaterialType::Phong;
    mat.kd = unitColor(m, "kd", glm::vec3(0.5f));
    mat.ks = unitColor(m, "ks", glm::vec3(0.5f));
    mat.exponent = m.numberOr("exponent", 20.0f);
    if (mat.exponent < 0.0f) m.at("exponent").fail("must be >= 0");
    // kd + ks <= 1 keeps the normalized Phong BRDF from reflecting more than it
    // receives (Lafortune & Willems 1994); a small tolerance absorbs decimal rounding.
    for (int c = 0; c < 3; ++c)
        if (mat.kd[c] + mat.ks[c] > 1.0f + 1e-6f)
            m.fail("kd + ks exceeds 1 in the " +
                   std::string(c == 0   ? "red"
                               : c == 1 ? "green"
                                        : "blue") +
                   " channel (" + std::to_string(mat.kd[c]) + " + " + std::to_string(mat.ks[c]) + ")");
}

// A factor in [0, 1] (glTF's metallic and roughness).
float unitNumber(const JsonReader& m, const char* key, float fallback) {
    float x = m.numberOr(key, fallback);
    if (x < 0.0f || x > 1.0f) m.at(key).fail("must be in [0, 1]");
    return x;
}

void parsePbr(const JsonReader& m, Material& mat) {
    m.expectKeys({"type", "base_color", "metallic", "roughness"}, "a pbr material");
    mat.type = MaterialType::Pbr;
    mat.pbr.baseColor = unitColor(m, "base_color", glm::vec3(0.8f));
    mat.pbr.metallic = unitNumber(m, "metallic", 0.0f);
    mat.pbr.roughness = unitNumber(m, "roughness", 0.5f);
}

}  // namespace

Material parseMaterial(const JsonReader& m, const std::string& name) {
    std::string type = m.has("type") ? m.at("type").choice({"diffuse", "phong", "pbr"}) : "diffuse";
    Material mat{name};
    if (type == "diffuse") parseDiffuse(m, mat);
    else if (type == "phong") parsePhong(m, mat);
    else parsePbr(m, mat);
    return mat;
}

}  // namespace penumbra
