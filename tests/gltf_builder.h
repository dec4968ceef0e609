// A builder of small glTF 2.0 files for tests: binary data in one buffer (a base64 data
// URI for .gltf, the BIN chunk for .glb), one bufferView and accessor per array.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace penumbra::test {

inline std::string base64(const std::vector<uint8_t>& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t n = uint32_t(bytes[i]) << 16;
        if (i + 1 < bytes.size()) n |= uint32_t(bytes[i + 1]) << 8;
        if (i + 2 < bytes.size()) n |= bytes[i + 2];
        out += table[(n >> 18) & 63];
        out += table[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(n >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[n & 63] : '=';
    }
    return out;
}

// Builds a glTF document: binary data goes into one buffer, each array into its own
// bufferView and accessor.
struct GltfBuilder {
    nlohmann::json doc = {
        {"asset", {{"version", "2.0"}}}, {"scenes", {{{"nodes", nlohmann::json::array()}}}}, {"scene", 0}};
    std::vector<uint8_t> bin;

    int addAccessor(const void* data, size_t bytes, int componentType, size_t count, const char* type,
                    size_t stride = 0) {
        while (bin.size() % 4) bin.push_back(0);
        nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (stride) view["byteStride"] = stride;
        bin.insert(bin.end(), static_cast<const uint8_t*>(data), static_cast<const uint8_t*>(data) + bytes);
        doc["bufferViews"].push_back(view);
        doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1},
                                    {"componentType", componentType},
                                    {"count", count},
                                    {"type", type}});
        return int(doc["accessors"].size()) - 1;
    }
    int positions(const std::vector<float>& p) {
        return addAccessor(p.data(), p.size() * 4, 5126, p.size() / 3, "VEC3");
    }
    int indices(const std::vector<uint32_t>& i) {
        return addAccessor(i.data(), i.size() * 4, 5125, i.size(), "SCALAR");
    }

    // A mesh with one primitive, instanced by a new root node; returns the node index.
    int addMeshNode(nlohmann::json primitive, nlohmann::json node = nlohmann::json::object()) {
        doc["meshes"].push_back({{"primitives", {primitive}}});
        node["mesh"] = doc["meshes"].size() - 1;
        return addNode(node);
    }
    int addNode(const nlohmann::json& node, bool root = true) {
        doc["nodes"].push_back(node);
        int index = int(doc["nodes"].size()) - 1;
        if (root) doc["scenes"][0]["nodes"].push_back(index);
        return index;
    }
    // The unit right triangle in the z = 0 plane, counter-clockwise seen from +z.
    nlohmann::json triangle() {
        return {{"attributes", {{"POSITION", positions({0, 0, 0, 1, 0, 0, 0, 1, 0})}}},
                {"indices", indices({0, 1, 2})}};
    }

    std::string gltf() const {
        nlohmann::json d = doc;
        d["buffers"] = {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
        return d.dump();
    }
    // GLB container: 12-byte header, a JSON chunk padded with spaces, a BIN chunk padded with zeros.
    std::string glb() const {
        nlohmann::json d = doc;
        d["buffers"] = {{{"byteLength", bin.size()}}};
        std::string text = d.dump();
        while (text.size() % 4) text += ' ';
        std::vector<uint8_t> data = bin;
        while (data.size() % 4) data.push_back(0);
        std::string out;
        auto u32 = [&out](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };  // little-endian host
        out += "glTF";
        u32(2);
        u32(uint32_t(12 + 8 + text.size() + 8 + data.size()));
        u32(uint32_t(text.size()));
        u32(0x4E4F534A);  // "JSON"
        out += text;
        u32(uint32_t(data.size()));
        u32(0x004E4942);  // "BIN\0"
        out.append(data.begin(), data.end());
        return out;
    }
};

}  // namespace penumbra::test
