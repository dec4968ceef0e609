// Wavefront OBJ meshes (see mesh_file.h): `v`, `vn`, `vt` and `f` with every index form
// (v, v/vt, v//vn, v/vt/vn; negative = counted back from the last one defined), polygons
// fanned from their first corner, `usemtl` splitting the faces into parts. Grouping and
// smoothing statements (o, g, s), `mtllib` (materials come from the scene file), lines and
// points are skipped; any other statement (free-form curves and surfaces) is refused rather
// than silently left out. Specification: the "Object Files (.obj)" appendix of Wavefront's
// Advanced Visualizer manual (the format's reference; Paul Bourke's copy is the usual one).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <unordered_map>

#include "core/errors.h"
#include "scene/mesh_file.h"

namespace penumbra::mesh_file_detail {
namespace {

// One face corner's indices into the file's v, vt and vn lists (0-based); -1 = not given.
struct Corner {
    int64_t v = -1, vt = -1, vn = -1;
};

// A part under construction: the shape and the map from corners to its vertices (one
// vertex per distinct corner, in order of first use). The vertices made from one position
// form a chain (head by position, then next), usually one or two long: faster than hashing.
struct PartBuilder {
    MeshPart part;
    std::vector<uint32_t> head;    // position v -> its first vertex + 1 (0: none yet)
    std::vector<uint32_t> next;    // vertex -> the next vertex of the same position + 1 (0: end)
    std::vector<Corner> cornerOf;  // vertex -> the corner it was made from
    bool anyNormal = false, anyWithoutNormal = false, anyUv = false;
};

class ObjReader {
public:
    ObjReader(const std::string& bytes, const std::string& label) : m_text(bytes), m_label(label) {}

    std::vector<MeshPart> read() {
        size_t start = 0;
        while (start < m_text.size()) {
            size_t end = m_text.find('\n', start);
            if (end == std::string_view::npos) end = m_text.size();
            ++m_line;
            statement(m_text.substr(start, end - start));
            start = end + 1;
        }
        std::vector<MeshPart> parts;
        for (PartBuilder& b : m_parts) {
            if (b.part.shape.indices.empty()) continue;
            if (b.anyNormal && b.anyWithoutNormal)
                fail(m_mixedNormalsLine, "faces with and without normals (vn) in one material's part");
            // Without any vn or vt the part has no normals or uvs, as a JSON mesh without them.
            if (!b.anyNormal) b.part.shape.normals.clear();
            if (!b.anyUv) b.part.shape.uvs.clear();
            parts.push_back(std::move(b.part));
        }
        if (parts.empty()) throwInputError(m_label, "", "no faces (f) in the file");
        return parts;
    }

private:
    [[noreturn]] void fail(size_t line, const std::string& why) const {
        throwInputError(m_label, "line " + std::to_string(line), why);
    }
    [[noreturn]] void fail(const std::string& why) const { fail(m_line, why); }

    // The next whitespace-separated token of `rest`, consumed; empty at the end.
    static std::string_view token(std::string_view& rest) {
        size_t b = rest.find_first_not_of(" \t\r");
        if (b == std::string_view::npos) {
            rest = {};
            return {};
        }
        size_t e = rest.find_first_of(" \t\r", b);
        if (e == std::string_view::npos) e = rest.size();
        std::string_view t = rest.substr(b, e - b);
        rest.remove_prefix(e);
        return t;
    }

    float number(std::string_view& rest, const char* what) const {
        std::string_view t = token(rest);
        if (t.empty()) fail(std::string("missing ") + what);
        float value = 0.0f;
        auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
        if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(value))
            fail("\"" + std::string(t) + "\" is not a finite number (" + what + ")");
        return value;
    }

    glm::vec3 vec3(std::string_view& rest, const char* what) const {
        glm::vec3 v;
        for (int c = 0; c < 3; ++c) v[c] = number(rest, what);
        return v;
    }

    void statement(std::string_view line) {
        if (size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        std::string_view rest = line;
        std::string_view keyword = token(rest);
        if (keyword.empty()) return;
        if (keyword == "v") {
            glm::vec3 p = vec3(rest, "vertex coordinate");
            if (!coordinateInRange(p)) fail("vertex must be within [-1e8, 1e8] (README: ranges)");
            m_positions.push_back(p);  // a w or vertex colours after x y z are ignored
        } else if (keyword == "vn") {
            m_normals.push_back(vec3(rest, "normal component"));  // checked where a face uses it
        } else if (keyword == "vt") {
            float u = number(rest, "texture coordinate");
            std::string_view more = rest;
            float v = token(more).empty() ? 0.0f : number(rest, "texture coordinate");
            m_uvs.emplace_back(u, 1.0f - v);  // v up in the file (mesh_file.h)
        } else if (keyword == "f") {
            face(rest);
        } else if (keyword == "usemtl") {
            std::string_view name = token(rest);
            if (name.empty()) fail("usemtl without a material name");
            selectPart(std::string(name));
        } else if (keyword == "o" || keyword == "g" || keyword == "s" || keyword == "mtllib" || keyword == "l" ||
                   keyword == "p" || keyword == "mg" || keyword == "usemap" || keyword == "maplib" ||
                   keyword == "lod" || keyword == "bevel" || keyword == "c_interp" || keyword == "d_interp" ||
                   keyword == "shadow_obj" || keyword == "trace_obj") {
            // Grouping, smoothing and display attributes: nothing to render.
        } else {
            fail("unsupported statement \"" + std::string(keyword) + "\" (meshes take v, vn, vt, f and usemtl)");
        }
    }

    void selectPart(const std::string& name) {
        auto [it, fresh] = m_partIndex.try_emplace(name, m_parts.size());
        if (fresh) {
            m_parts.emplace_back();
            m_parts.back().part.material = name;
        }
        m_current = it->second;
    }

    // Resolves one OBJ index (1-based, or negative from the end) against `count` entries.
    int64_t resolve(std::string_view t, size_t count, const char* list) const {
        int64_t i = 0;
        auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), i);
        if (ec != std::errc() || end != t.data() + t.size())
            fail("\"" + std::string(t) + "\" is not an index into " + list);
        int64_t resolved = i > 0 ? i - 1 : int64_t(count) + i;
        if (i == 0 || resolved < 0 || resolved >= int64_t(count))
            fail(std::string(list) + " index " + std::string(t) + " out of range (" + std::to_string(count) +
                 " defined so far)");
        return resolved;
    }

    Corner corner(std::string_view t) const {
        Corner c;
        size_t s1 = t.find('/');
        c.v = resolve(t.substr(0, s1), m_positions.size(), "vertex (v)");
        if (s1 == std::string_view::npos) return c;
        std::string_view rest = t.substr(s1 + 1);
        size_t s2 = rest.find('/');
        std::string_view vt = rest.substr(0, s2);
        if (!vt.empty()) c.vt = resolve(vt, m_uvs.size(), "texture coordinate (vt)");
        if (s2 == std::string_view::npos) return c;
        std::string_view vn = rest.substr(s2 + 1);
        if (vn.empty() && vt.empty()) fail("\"" + std::string(t) + "\": an index form is v, v/vt, v//vn or v/vt/vn");
        if (!vn.empty()) c.vn = resolve(vn, m_normals.size(), "normal (vn)");
        return c;
    }

    uint32_t vertexOf(PartBuilder& b, const Corner& c) {
        if (c.vt >= 0) b.anyUv = true;
        if (b.head.size() <= size_t(c.v)) b.head.resize(std::max(size_t(c.v) + 1, 2 * b.head.size()), 0);
        uint32_t* link = &b.head[size_t(c.v)];
        while (*link != 0) {
            const uint32_t vertex = *link - 1;
            const Corner& seen = b.cornerOf[vertex];
            if (seen.vt == c.vt && seen.vn == c.vn) return vertex;
            link = &b.next[vertex];
        }
        Shape& s = b.part.shape;
        if (s.positions.size() >= UINT32_MAX - 1) fail("more than 2^32 - 2 vertices");
        const uint32_t vertex = uint32_t(s.positions.size());
        *link = vertex + 1;  // before the push_backs below, which may move b.next
        b.next.push_back(0);
        b.cornerOf.push_back(c);
        s.positions.push_back(m_positions[size_t(c.v)]);
        s.uvs.push_back(c.vt >= 0 ? m_uvs[size_t(c.vt)] : glm::vec2(0.0f));
        glm::vec3 n(0.0f);
        if (c.vn >= 0) {
            auto unit = unitNormal(m_normals[size_t(c.vn)]);
            if (!unit) fail("normal (vn) " + std::to_string(c.vn + 1) + " has zero length");
            n = *unit;
        }
        s.normals.push_back(n);
        return vertex;
    }

    void face(std::string_view rest) {
        if (m_parts.empty()) selectPart("");
        PartBuilder& b = m_parts[m_current];
        m_faceVertices.clear();
        bool withNormal = false, withoutNormal = false;
        for (std::string_view t = token(rest); !t.empty(); t = token(rest)) {
            Corner c = corner(t);
            (c.vn >= 0 ? withNormal : withoutNormal) = true;
            m_faceVertices.push_back(vertexOf(b, c));
        }
        if (m_faceVertices.size() < 3) fail("a face needs at least 3 vertices");
        if (withNormal) b.anyNormal = true;
        if (withoutNormal) b.anyWithoutNormal = true;
        if (b.anyNormal && b.anyWithoutNormal && m_mixedNormalsLine == 0) m_mixedNormalsLine = m_line;
        Shape& s = b.part.shape;
        // A fan from the first corner: exact for convex polygons, as OBJ exporters write them.
        for (size_t k = 1; k + 1 < m_faceVertices.size(); ++k) {
            const uint32_t i0 = m_faceVertices[0], i1 = m_faceVertices[k], i2 = m_faceVertices[k + 1];
            if (auto why = triangleProblem(s.positions[i0], s.positions[i1], s.positions[i2]))
                fail(*why + (m_faceVertices.size() > 3 ? " (fan triangle " + std::to_string(k - 1) + ")" : ""));
            s.indices.insert(s.indices.end(), {i0, i1, i2});
        }
        if (s.indices.size() > size_t(UINT32_MAX)) fail("more than 2^32 - 1 indices");
    }

    std::string_view m_text;
    const std::string& m_label;
    size_t m_line = 0;
    size_t m_mixedNormalsLine = 0;
    std::vector<glm::vec3> m_positions, m_normals;
    std::vector<glm::vec2> m_uvs;
    std::vector<PartBuilder> m_parts;
    std::unordered_map<std::string, size_t> m_partIndex;
    size_t m_current = 0;
    std::vector<uint32_t> m_faceVertices;
};

}  // namespace

std::vector<MeshPart> readObj(const std::string& bytes, const std::string& label) {
    return ObjReader(bytes, label).read();
}

}  // namespace penumbra::mesh_file_detail
