// to_world parsing and application (see transform.h).
#include "scene/transform.h"

#include <cmath>
#include <numbers>
#include <utility>

namespace penumbra {

namespace {

// Rodrigues' rotation formula: R = cos a I + sin a [k]x + (1 - cos a) k k^T, k the unit axis
// (counter-clockwise about k when looking down it, right-handed, as pbrt's Rotate).
glm::dmat3 rotation(glm::dvec3 k, double degrees) {
    const double a = degrees * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
    glm::dmat3 r;  // glm is column-major: r[col][row]
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) r[col][row] = (row == col ? c : 0.0) + (1.0 - c) * k[row] * k[col];
    r[1][0] -= s * k.z;  // row 0, col 1
    r[2][0] += s * k.y;
    r[0][1] += s * k.z;
    r[2][1] -= s * k.x;
    r[0][2] -= s * k.y;
    r[1][2] += s * k.x;
    return r;
}

glm::dvec3 vec3Of(const JsonReader& r) { return glm::dvec3(r.vec3()); }

Affine readMatrix(const JsonReader& r) {
    if (r.size() != 4) r.fail("a to_world matrix has 4 rows of 4 numbers");
    Affine m;
    for (size_t row = 0; row < 4; ++row) {
        std::vector<float> v = r[row].numbers();
        if (v.size() != 4) r[row].fail("a to_world matrix has 4 rows of 4 numbers");
        if (row == 3) {
            if (v[0] != 0.0f || v[1] != 0.0f || v[2] != 0.0f || v[3] != 1.0f)
                r[row].fail("the last row must be [0, 0, 0, 1] (an affine map)");
            break;
        }
        for (size_t col = 0; col < 3; ++col) m.linear[col][row] = v[col];
        m.translation[int(row)] = v[3];
    }
    return m;
}

Affine readParts(const JsonReader& r) {
    r.expectKeys({"scale", "rotate", "translate"}, "to_world");
    glm::dvec3 scale(1.0);
    if (auto s = r.find("scale")) {
        scale = s->json().is_number() ? glm::dvec3(double(s->number())) : vec3Of(*s);
        if (scale.x == 0.0 || scale.y == 0.0 || scale.z == 0.0) s->fail("a scale of 0 is not invertible");
    }
    glm::dmat3 rotate(1.0);
    if (auto rot = r.find("rotate")) {
        rot->expectKeys({"axis", "angle"}, "rotate");
        glm::dvec3 axis = vec3Of(rot->at("axis"));
        const double len = glm::length(axis);
        if (!(len > 0.0) || !std::isfinite(len)) rot->at("axis").fail("must be a non-zero vector");
        rotate = rotation(axis / len, rot->at("angle").number());
    }
    Affine m;
    m.linear = rotate * glm::dmat3(glm::dvec3(scale.x, 0, 0), glm::dvec3(0, scale.y, 0), glm::dvec3(0, 0, scale.z));
    if (auto t = r.find("translate")) m.translation = vec3Of(*t);
    return m;
}

}  // namespace

Affine readToWorld(const JsonReader& r) {
    Affine m = r.json().is_array() ? readMatrix(r) : r.json().is_object() ? readParts(r) : Affine{};
    if (!r.json().is_array() && !r.json().is_object())
        r.fail("expected a 4x4 matrix (4 rows of 4 numbers) or {\"scale\", \"rotate\", \"translate\"}");
    const double det = glm::determinant(m.linear);
    // Relative to the columns' lengths, so that a uniformly tiny scale is not "singular".
    const double size = glm::length(m.linear[0]) * glm::length(m.linear[1]) * glm::length(m.linear[2]);
    if (!std::isfinite(det) || !(std::fabs(det) > 1e-12 * size)) r.fail("not invertible (its determinant is 0)");
    return m;
}

std::optional<double> uniformScaleOf(const Affine& m) {
    // L = s Q with Q orthogonal exactly when L^T L = s^2 I.
    const glm::dmat3 g = glm::transpose(m.linear) * m.linear;
    const double s2 = (g[0][0] + g[1][1] + g[2][2]) / 3.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (std::fabs(g[i][j] - (i == j ? s2 : 0.0)) > 1e-6 * s2) return std::nullopt;
    return std::sqrt(s2);
}

bool turnsNothing(const Affine& m) {
    const double s = m.linear[0][0];
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row)
            if (std::fabs(m.linear[col][row] - (row == col ? s : 0.0)) > 1e-6 * std::fabs(s)) return false;
    return s > 0.0;
}

glm::vec3 transformPoint(const Affine& m, glm::vec3 p) { return glm::vec3(m.linear * glm::dvec3(p) + m.translation); }

glm::vec3 transformVector(const Affine& m, glm::vec3 v) { return glm::vec3(m.linear * glm::dvec3(v)); }

bool mirrors(const Affine& m) { return glm::determinant(m.linear) < 0.0; }

void transformMesh(const Affine& m, Shape& s) {
    for (glm::vec3& p : s.positions) p = transformPoint(m, p);
    // Normals are perpendicular to tangents t: n^T t = 0 is kept by n' = L^-T n (L the
    // linear part), since (L^-T n)^T (L t) = n^T t (pbrt-v4, section 3.10.3, "Normals").
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(m.linear));
    for (glm::vec3& n : s.normals) n = glm::vec3(glm::normalize(normalMatrix * glm::dvec3(n)));
    // Tangents are surface directions: through L itself. A mirror flips the frame's
    // handedness against the transformed normal, hence w (as in load_gltf.cpp, readTangents).
    for (glm::vec4& t : s.tangents)
        t = glm::vec4(glm::normalize(glm::vec3(m.linear * glm::dvec3(t))), mirrors(m) ? -t.w : t.w);
    if (mirrors(m))
        for (size_t t = 0; t + 2 < s.indices.size(); t += 3) std::swap(s.indices[t + 1], s.indices[t + 2]);
}

void transformQuad(const Affine& m, Shape& s) {
    const glm::vec3 u = transformVector(m, s.edgeU), v = transformVector(m, s.edgeV);
    if (mirrors(m)) {
        s.origin = transformPoint(m, s.origin + s.edgeU);
        s.edgeU = -u;
    } else {
        s.origin = transformPoint(m, s.origin);
        s.edgeU = u;
    }
    s.edgeV = v;
}

void transformLight(const Affine& m, Light& light) {
    if (light.type == LightType::Point || light.type == LightType::Spot)
        light.position = transformPoint(m, light.position);
    if (light.type == LightType::Directional || light.type == LightType::Spot)
        light.direction = glm::vec3(glm::normalize(m.linear * glm::dvec3(light.direction)));
}

}  // namespace penumbra
