// Per-vertex tangents of normal-mapped meshes (see tangents.h).
#include "scene/tangents.h"

#include <cmath>

namespace penumbra {

glm::vec3 perpendicularTo(glm::vec3 n) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z), b = n.x * n.y * a;
    return glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
}

namespace {

// v without its component along unit n, normalized; zero where nothing is left.
glm::dvec3 projectedUnit(glm::dvec3 v, glm::dvec3 n) {
    glm::dvec3 p = v - n * glm::dot(n, v);
    double len = glm::length(p);
    return len > 1e-20 && std::isfinite(len) ? p / len : glm::dvec3(0.0);
}

// The angle of the triangle's corner at p between the edges to q and r (0 if degenerate).
double cornerAngle(glm::dvec3 p, glm::dvec3 q, glm::dvec3 r) {
    glm::dvec3 a = q - p, b = r - p;
    double la = glm::length(a), lb = glm::length(b);
    if (!(la > 0.0 && lb > 0.0)) return 0.0;
    return std::acos(glm::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0));
}

}  // namespace

void computeTangents(Shape& s) {
    const size_t n = s.positions.size();
    // tSum: along increasing u; upSum: along decreasing v, the image's up (v = 0 is the top row),
    // which a glTF normal map's +Y points along (glTF 2.0 section 3.9.3).
    std::vector<glm::dvec3> tSum(n, glm::dvec3(0.0)), upSum(n, glm::dvec3(0.0)), faceN(n, glm::dvec3(0.0));
    for (size_t t = 0; t + 2 < s.indices.size(); t += 3) {
        const uint32_t v[3] = {s.indices[t], s.indices[t + 1], s.indices[t + 2]};
        const glm::dvec3 p[3] = {s.positions[v[0]], s.positions[v[1]], s.positions[v[2]]};
        glm::dvec2 uv[3] = {};
        if (!s.uvs.empty()) uv[0] = s.uvs[v[0]], uv[1] = s.uvs[v[1]], uv[2] = s.uvs[v[2]];
        const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
        const glm::dvec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
        const glm::dvec3 face = glm::cross(e1, e2);
        // dp/du and dp/dv from e = dp/du du + dp/dv dv for both edges (Lengyel 2001); the
        // determinant's sign is the uv mapping's handedness and is kept in the bitangent.
        const double det = d1.x * d2.y - d2.x * d1.y;
        const bool uvsOk = std::fabs(det) > 1e-30 && std::isfinite(det);
        const glm::dvec3 dpdu = uvsOk ? (e1 * d2.y - e2 * d1.y) / det : glm::dvec3(0.0);
        const glm::dvec3 dpdv = uvsOk ? (e2 * d1.x - e1 * d2.x) / det : glm::dvec3(0.0);
        for (int c = 0; c < 3; ++c) {
            faceN[v[c]] += face;  // the flat normal of vertices without one (area weighted)
            if (!uvsOk) continue;
            const double w = cornerAngle(p[c], p[(c + 1) % 3], p[(c + 2) % 3]);
            const double faceLen = glm::length(face);
            const glm::dvec3 nc = s.normals.empty() ? face / faceLen : glm::dvec3(s.normals[v[c]]);
            tSum[v[c]] += w * projectedUnit(dpdu, nc);
            upSum[v[c]] += w * projectedUnit(-dpdv, nc);
        }
    }
    s.tangents.assign(n, glm::vec4(0.0f));
    for (size_t i = 0; i < n; ++i) {
        glm::dvec3 nv = s.normals.empty() ? faceN[i] : glm::dvec3(s.normals[i]);
        const double len = glm::length(nv);
        if (!(len > 0.0) || !std::isfinite(len)) continue;  // a vertex no triangle uses
        nv /= len;
        glm::dvec3 t = projectedUnit(tSum[i], nv);  // Gram-Schmidt against the vertex normal
        if (t == glm::dvec3(0.0)) t = glm::dvec3(perpendicularTo(glm::vec3(nv)));
        const double w = glm::dot(glm::cross(nv, t), upSum[i]) < 0.0 ? -1.0 : 1.0;
        s.tangents[i] = glm::vec4(glm::vec3(t), float(w));
    }
}

}  // namespace penumbra
