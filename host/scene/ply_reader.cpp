// PLY meshes (see mesh_file.h): ASCII and binary (little- and big-endian), Greg Turk's format
// as Paul Bourke documents it ("PLY - Polygon File Format"): a text header of elements and
// their properties, then the elements in header order. From `vertex`: x y z, optional
// nx ny nz and one texture pair of u v / s t / texture_u texture_v / texture_s texture_t;
// from `face`: the list vertex_indices (or vertex_index), polygons fanned from their first
// corner. Every other element and property is read past. Counts are checked against the
// bytes left before anything is allocated for them, so a header cannot ask for gigabytes.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "core/errors.h"
#include "scene/mesh_file.h"

namespace penumbra::mesh_file_detail {
namespace {

enum class Format { Ascii, BinaryLittle, BinaryBig };
enum class Type { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

std::optional<Type> typeOf(std::string_view name) {
    if (name == "char" || name == "int8") return Type::Int8;
    if (name == "uchar" || name == "uint8") return Type::Uint8;
    if (name == "short" || name == "int16") return Type::Int16;
    if (name == "ushort" || name == "uint16") return Type::Uint16;
    if (name == "int" || name == "int32") return Type::Int32;
    if (name == "uint" || name == "uint32") return Type::Uint32;
    if (name == "float" || name == "float32") return Type::Float32;
    if (name == "double" || name == "float64") return Type::Float64;
    return std::nullopt;
}

size_t sizeOf(Type t) {
    switch (t) {
        case Type::Int8:
        case Type::Uint8: return 1;
        case Type::Int16:
        case Type::Uint16: return 2;
        case Type::Int32:
        case Type::Uint32:
        case Type::Float32: return 4;
        case Type::Float64: return 8;
    }
    return 1;
}

bool isInteger(Type t) { return t != Type::Float32 && t != Type::Float64; }

struct Property {
    std::string name;
    Type type = Type::Float32;
    bool list = false;
    Type countType = Type::Uint8;  // for lists
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
};

// Where a value is read, for messages: element instance `index` of `element` (made into
// text only when something fails).
struct At {
    const Element* element;
    uint64_t index;
};

// What the vertex and face elements hold, as indices into their property lists (-1: none).
struct VertexLayout {
    int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1, u = -1, v = -1;
};

class PlyReader {
public:
    PlyReader(const std::string& bytes, const std::string& label) : m_bytes(bytes), m_label(label) {}

    std::vector<MeshPart> read() {
        header();
        MeshPart part;
        Shape& s = part.shape;
        bool sawFaces = false;
        for (const Element& e : m_elements) {
            if (e.name == "vertex") vertices(e, s);
            else if (e.name == "face") {
                faces(e, s);
                sawFaces = true;
            } else {
                for (uint64_t i = 0; i < e.count; ++i) skipElement(e, i);
            }
        }
        if (!sawFaces || s.indices.empty()) throwInputError(m_label, "", "no faces (a mesh needs a face element)");
        std::vector<MeshPart> parts;
        parts.push_back(std::move(part));
        return parts;
    }

private:
    [[noreturn]] void fail(const std::string& where, const std::string& why) const {
        throwInputError(m_label, where, why);
    }
    [[noreturn]] void fail(At at, const std::string& why) const {
        fail(at.element->name + " " + std::to_string(at.index), why);
    }

    // ------------------------------------------------------------------ header

    void header() {
        size_t line = 0;
        auto nextLine = [&]() -> std::string_view {
            if (m_pos >= m_bytes.size()) fail("header", "ends before end_header");
            size_t end = m_bytes.find('\n', m_pos);
            if (end == std::string_view::npos) fail("header", "ends before end_header");
            std::string_view l = m_bytes.substr(m_pos, end - m_pos);
            if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
            m_pos = end + 1;
            ++line;
            return l;
        };
        auto bad = [&](const std::string& why) { fail("header line " + std::to_string(line), why); };
        if (nextLine() != "ply") fail("header", "not a PLY file (it must begin with the line \"ply\")");
        bool formatSeen = false;
        for (;;) {
            std::string_view l = nextLine();
            std::vector<std::string_view> w = words(l);
            if (w.empty()) continue;
            if (w[0] == "end_header") break;
            if (w[0] == "comment" || w[0] == "obj_info") continue;
            if (w[0] == "format") {
                if (w.size() != 3) bad("expected \"format ascii|binary_little_endian|binary_big_endian 1.0\"");
                if (w[1] == "ascii") m_format = Format::Ascii;
                else if (w[1] == "binary_little_endian") m_format = Format::BinaryLittle;
                else if (w[1] == "binary_big_endian") m_format = Format::BinaryBig;
                else bad("unknown format \"" + std::string(w[1]) + "\"");
                if (w[2] != "1.0") bad("unsupported version " + std::string(w[2]) + " (1.0 is)");
                formatSeen = true;
            } else if (w[0] == "element") {
                if (w.size() != 3) bad("expected \"element NAME COUNT\"");
                Element e;
                e.name = w[1];
                auto [end, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
                if (ec != std::errc() || end != w[2].data() + w[2].size())
                    bad("bad element count \"" + std::string(w[2]) + "\"");
                for (const Element& other : m_elements)
                    if (other.name == e.name) bad("a second element \"" + e.name + "\"");
                m_elements.push_back(std::move(e));
            } else if (w[0] == "property") {
                if (m_elements.empty()) bad("property before any element");
                Property p;
                if (w.size() == 5 && w[1] == "list") {
                    auto count = typeOf(w[2]), item = typeOf(w[3]);
                    if (!count || !isInteger(*count))
                        bad("list count type \"" + std::string(w[2]) + "\" is not an integer type");
                    if (!item) bad("unknown property type \"" + std::string(w[3]) + "\"");
                    p.list = true;
                    p.countType = *count;
                    p.type = *item;
                    p.name = w[4];
                } else if (w.size() == 3) {
                    auto t = typeOf(w[1]);
                    if (!t) bad("unknown property type \"" + std::string(w[1]) + "\"");
                    p.type = *t;
                    p.name = w[2];
                } else {
                    bad("expected \"property TYPE NAME\" or \"property list COUNT_TYPE TYPE NAME\"");
                }
                m_elements.back().properties.push_back(std::move(p));
            } else {
                bad("unknown header keyword \"" + std::string(w[0]) + "\"");
            }
        }
        if (!formatSeen) fail("header", "no format line");
        // Every element instance takes at least one byte (binary) or one character per
        // property (ASCII): counts beyond the bytes left are corrupt.
        const uint64_t left = m_bytes.size() - m_pos;
        for (const Element& e : m_elements) {
            uint64_t perInstance = 0;
            for (const Property& p : e.properties) perInstance += p.list ? sizeOf(p.countType) : sizeOf(p.type);
            if (m_format == Format::Ascii) perInstance = e.properties.size();
            // An element without properties holds nothing, so any count of it is corrupt too
            // (and would only spin through the count).
            perInstance = std::max<uint64_t>(perInstance, 1);
            if (e.count > left / perInstance)
                fail("header", "element " + e.name + " claims " + std::to_string(e.count) +
                                   " entries, more than the file's remaining " + std::to_string(left) + " bytes hold");
        }
    }

    static std::vector<std::string_view> words(std::string_view l) {
        std::vector<std::string_view> w;
        size_t i = 0;
        while (i < l.size()) {
            while (i < l.size() && (l[i] == ' ' || l[i] == '\t')) ++i;
            size_t b = i;
            while (i < l.size() && l[i] != ' ' && l[i] != '\t') ++i;
            if (i > b) w.push_back(l.substr(b, i - b));
        }
        return w;
    }

    // ------------------------------------------------------------------ values

    // The next value of type `t`, as a double (every PLY type fits one exactly).
    double value(Type t, At at) {
        if (m_format == Format::Ascii) return asciiValue(t, at);
        const size_t n = sizeOf(t);
        if (m_bytes.size() - m_pos < n) fail(at, "the file ends inside this element");
        unsigned char b[8];
        std::memcpy(b, m_bytes.data() + m_pos, n);
        m_pos += n;
        const bool swap = (m_format == Format::BinaryBig) == (std::endian::native == std::endian::little);
        if (swap)
            for (size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
        switch (t) {
            case Type::Int8: return double(int8_t(b[0]));
            case Type::Uint8: return double(b[0]);
            case Type::Int16: {
                int16_t v;
                std::memcpy(&v, b, 2);
                return v;
            }
            case Type::Uint16: {
                uint16_t v;
                std::memcpy(&v, b, 2);
                return v;
            }
            case Type::Int32: {
                int32_t v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case Type::Uint32: {
                uint32_t v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case Type::Float32: {
                float v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case Type::Float64: {
                double v;
                std::memcpy(&v, b, 8);
                return v;
            }
        }
        return 0.0;
    }

    double asciiValue(Type t, At at) {
        while (m_pos < m_bytes.size() && std::isspace(static_cast<unsigned char>(m_bytes[m_pos]))) ++m_pos;
        size_t b = m_pos;
        while (m_pos < m_bytes.size() && !std::isspace(static_cast<unsigned char>(m_bytes[m_pos]))) ++m_pos;
        std::string_view word = m_bytes.substr(b, m_pos - b);
        if (word.empty()) fail(at, "the file ends inside this element");
        double v = 0.0;
        std::from_chars_result r{};
        if (isInteger(t)) {
            int64_t i = 0;
            r = std::from_chars(word.data(), word.data() + word.size(), i);
            v = double(i);
        } else {
            r = std::from_chars(word.data(), word.data() + word.size(), v);
        }
        if (r.ec != std::errc() || r.ptr != word.data() + word.size())
            fail(at, "\"" + std::string(word) + "\" is not a" + (isInteger(t) ? "n integer" : " number"));
        return v;
    }

    // The item count of a list property, checked against the bytes left.
    uint64_t listCount(const Property& p, At at) {
        double c = value(p.countType, at);
        if (c < 0) fail(at, "negative list length");
        if (uint64_t(c) > m_bytes.size() - m_pos)
            fail(at, "list length " + std::to_string(uint64_t(c)) + " runs past the file's end");
        return uint64_t(c);
    }

    void skipElement(const Element& e, uint64_t i) {
        const At at{&e, i};
        for (const Property& p : e.properties) {
            uint64_t n = p.list ? listCount(p, at) : 1;
            for (uint64_t k = 0; k < n; ++k) value(p.type, at);
        }
    }

    // ------------------------------------------------------------------ vertex and face

    void vertices(const Element& e, Shape& s) {
        VertexLayout l;
        for (size_t i = 0; i < e.properties.size(); ++i) {
            const Property& p = e.properties[i];
            if (p.list) continue;
            int* slot = p.name == "x"                                                                        ? &l.x
                        : p.name == "y"                                                                      ? &l.y
                        : p.name == "z"                                                                      ? &l.z
                        : p.name == "nx"                                                                     ? &l.nx
                        : p.name == "ny"                                                                     ? &l.ny
                        : p.name == "nz"                                                                     ? &l.nz
                        : (p.name == "u" || p.name == "s" || p.name == "texture_u" || p.name == "texture_s") ? &l.u
                        : (p.name == "v" || p.name == "t" || p.name == "texture_v" || p.name == "texture_t") ? &l.v
                                                                                                             : nullptr;
            if (slot && *slot < 0) *slot = int(i);
        }
        if (l.x < 0 || l.y < 0 || l.z < 0) fail("header", "the vertex element needs properties x, y and z");
        const bool normals = l.nx >= 0 && l.ny >= 0 && l.nz >= 0, uvs = l.u >= 0 && l.v >= 0;
        if (e.count > UINT32_MAX) fail("header", "more than 2^32 - 1 vertices");
        s.positions.reserve(e.count);
        if (normals) s.normals.reserve(e.count);
        if (uvs) s.uvs.reserve(e.count);
        std::vector<double> values(e.properties.size(), 0.0);
        for (uint64_t i = 0; i < e.count; ++i) {
            const At at{&e, i};
            for (size_t k = 0; k < e.properties.size(); ++k) {
                const Property& p = e.properties[k];
                if (!p.list) {
                    values[k] = value(p.type, at);
                    continue;
                }
                uint64_t n = listCount(p, at);
                for (uint64_t j = 0; j < n; ++j) value(p.type, at);
            }
            // Braces: with parentheses this reads as a function declaration (the most vexing parse).
            const glm::vec3 pos{float(values[size_t(l.x)]), float(values[size_t(l.y)]), float(values[size_t(l.z)])};
            if (!coordinateInRange(pos)) fail(at, "position must be finite and within [-1e8, 1e8] (README: ranges)");
            s.positions.push_back(pos);
            if (normals) {
                auto unit = unitNormal(
                    glm::vec3(float(values[size_t(l.nx)]), float(values[size_t(l.ny)]), float(values[size_t(l.nz)])));
                if (!unit) fail(at, "normal has zero or non-finite length");
                s.normals.push_back(*unit);
            }
            if (uvs) {
                const glm::vec2 uv{float(values[size_t(l.u)]),
                                   1.0f - float(values[size_t(l.v)])};  // v up (mesh_file.h)
                if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) fail(at, "texture coordinate is not finite");
                s.uvs.push_back(uv);
            }
        }
    }

    void faces(const Element& e, Shape& s) {
        int indexProperty = -1;
        for (size_t i = 0; i < e.properties.size(); ++i)
            if (e.properties[i].list &&
                (e.properties[i].name == "vertex_indices" || e.properties[i].name == "vertex_index"))
                indexProperty = int(i);
        if (indexProperty < 0) fail("header", "the face element needs a list property vertex_indices");
        if (!isInteger(e.properties[size_t(indexProperty)].type)) fail("header", "vertex_indices must hold integers");
        std::vector<uint32_t> corners;
        for (uint64_t i = 0; i < e.count; ++i) {
            const At at{&e, i};
            for (size_t k = 0; k < e.properties.size(); ++k) {
                const Property& p = e.properties[k];
                uint64_t n = p.list ? listCount(p, at) : 1;
                if (int(k) != indexProperty) {
                    for (uint64_t j = 0; j < n; ++j) value(p.type, at);
                    continue;
                }
                if (n < 3) fail(at, "a face needs at least 3 vertices");
                corners.clear();
                for (uint64_t j = 0; j < n; ++j) {
                    double v = value(p.type, at);
                    if (!(v >= 0.0) || v >= double(s.positions.size()))
                        fail(at, "vertex index " + std::to_string(int64_t(v)) + " out of range (" +
                                     std::to_string(s.positions.size()) + " vertices before this face)");
                    corners.push_back(uint32_t(v));
                }
                // A fan from the first corner, as for OBJ polygons.
                for (size_t j = 1; j + 1 < corners.size(); ++j) {
                    if (auto why = triangleProblem(s.positions[corners[0]], s.positions[corners[j]],
                                                   s.positions[corners[j + 1]]))
                        fail(at, *why + (corners.size() > 3 ? " (fan triangle " + std::to_string(j - 1) + ")" : ""));
                    s.indices.insert(s.indices.end(), {corners[0], corners[j], corners[j + 1]});
                }
                if (s.indices.size() > size_t(UINT32_MAX)) fail(at, "more than 2^32 - 1 indices");
            }
        }
    }

    std::string_view m_bytes;
    const std::string& m_label;
    size_t m_pos = 0;
    Format m_format = Format::Ascii;
    std::vector<Element> m_elements;
};

}  // namespace

std::vector<MeshPart> readPly(const std::string& bytes, const std::string& label) {
    return PlyReader(bytes, label).read();
}

}  // namespace penumbra::mesh_file_detail
