// The input rules for glTF files, applied around tinygltf: the GLB header, the JSON rules
// every reader shares, the version, integer properties, and file access confined to the
// model's folder. The import itself is load_gltf.cpp's.
#include "scene/gltf_input_rules.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>

#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/input_file.h"
#include "scene/gltf_extensions.h"
#include "scene/json_parse.h"

namespace penumbra {
namespace {

// glTF properties whose values are integers (indices, counts, enums; glTF 2.0 schema).
// tinygltf ignores a non-integral one as if absent (node.mesh 0.5: no mesh) or truncates
// it (a light index 0.5: light 0); here it is refused. "attributes" and "targets" map
// names to integers; the others are integers or arrays of them.
enum class Integers { No, Numbers, Members };

Integers integersOf(const std::string& key) {
    static const char* names[] = {"scene",      "nodes",     "children",      "mesh",       "camera",
                                  "skin",       "buffer",    "bufferView",    "byteOffset", "byteLength",
                                  "byteStride", "count",     "componentType", "indices",    "material",
                                  "mode",       "source",    "sampler",       "index",      "texCoord",
                                  "light",      "magFilter", "minFilter",     "wrapS",      "wrapT",
                                  "input",      "output",    "node",          "joints",     "inverseBindMatrices",
                                  "skeleton"};
    if (key == "attributes" || key == "targets") return Integers::Members;
    bool listed = std::any_of(std::begin(names), std::end(names), [&](const char* n) { return key == n; });
    return listed ? Integers::Numbers : Integers::No;
}

// Walks the document (at most kMaxJsonDepth deep, checked before); "extras" hold the
// author's own data and are skipped.
void checkIntegers(const nlohmann::json& value, const std::string& path, Integers mode, const std::string& label) {
    if (value.is_number_float()) {
        double x = value.get<double>();
        if (mode != Integers::No && x != std::floor(x))
            throwInputError(label, path, "expected an integer, got " + value.dump());
    } else if (value.is_array()) {
        for (size_t i = 0; i < value.size(); ++i)
            checkIntegers(value[i], path + "[" + std::to_string(i) + "]", mode, label);
    } else if (value.is_object()) {
        for (const auto& item : value.items()) {
            if (item.key() == "extras") continue;
            std::string child = path.empty() ? item.key() : path + "." + item.key();
            checkIntegers(item.value(), child, mode == Integers::Members ? Integers::Numbers : integersOf(item.key()),
                          label);
        }
    }
}

// The URI as written in the file: tinygltf joined it to the model's folder or to ".".
std::string uriOf(const std::string& path, const GltfFileAccess& access) {
    std::string folder = access.folder.string();
    if (!folder.empty() && path.rfind(folder + "/", 0) == 0) return path.substr(folder.size() + 1);
    if (path.rfind("./", 0) == 0) return path.substr(2);
    return path;
}

bool permitted(const std::string& path, GltfFileAccess& access) {
    if (allowAnyPath() || isInsideFolder(path, access.folder)) return true;
    if (access.refused.empty()) access.refused = uriOf(path, access);
    return false;
}

// tinygltf looks for a relative URI in the model's folder, then in the working directory:
// only a file that exists is refused, so that a missing one reads "not found".
bool confinedFileExists(const std::string& path, void* user) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return false;
    return permitted(path, *static_cast<GltfFileAccess*>(user));
}

// tinygltf's own version runs wordexp on every URI; a path is only a path here.
std::string keepPath(const std::string& path, void*) { return path; }

bool confinedReadWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    auto& access = *static_cast<GltfFileAccess*>(user);
    if (!permitted(path, access)) return false;
    try {
        std::string bytes = readInputFile(path, uriOf(path, access), kMaxModelFileBytes);
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const InputError& e) {
        if (access.failed.empty()) access.failed = e.what();
        if (err) *err += std::string(e.what()) + "\n";
        return false;
    }
}

bool refuseWrite(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }

}  // namespace

// The JSON chunk of a .glb (glTF 2.0 §4.4: a 12-byte header, then chunks of length,
// type, data; the first is JSON). Container version 1 (the glTF 1.0 binary extension)
// is refused: its layout and meaning differ.
std::string_view glbJsonChunk(const std::string& bytes, const std::string& label) {
    auto word = [&](size_t offset) {
        uint32_t value = 0;
        std::memcpy(&value, bytes.data() + offset, 4);
        return value;
    };
    if (bytes.size() < 20) throwInputError(label, "", "GLB file too short for its header");
    if (word(4) != 2)
        throwInputError(label, "",
                        "GLB container version " + std::to_string(word(4)) + " is not supported (glTF 2.0 only)");
    uint32_t length = word(12);
    if (word(16) != 0x4E4F534Au) throwInputError(label, "", "GLB file does not start with a JSON chunk");
    if (length > bytes.size() - 20) throwInputError(label, "", "GLB JSON chunk runs past the end of the file");
    return std::string_view(bytes).substr(20, length);
}

// The input rules every JSON reader shares (depth, duplicate keys, syntax without echo),
// applied before tinygltf, whose value conversion recurses; then the version: glTF 1.0
// files parse as JSON but mean something else.
std::vector<std::string> checkGltfDocument(std::string_view json, const std::string& label) {
    nlohmann::json doc = parseJsonText(json, label);
    if (!doc.is_object()) throwInputError(label, "", "expected a JSON object");
    auto asset = doc.find("asset");
    if (asset == doc.end() || !asset->is_object()) throwInputError(label, "asset", "missing (glTF 2.0 requires it)");
    auto version = asset->find("version");
    if (version == asset->end() || !version->is_string())
        throwInputError(label, "asset.version", "expected a string such as \"2.0\"");
    std::string v = version->get<std::string>();
    if (v.substr(0, 2) != "2.")
        throwInputError(label, "asset.version", "\"" + v + "\" is not supported (glTF 2.x only)");
    checkIntegers(doc, "", Integers::No, label);
    // tinygltf joins every URI to a folder, so an absolute one would read as "not found":
    // say why it is refused instead (the relative ones are checked as they are opened).
    for (const char* array : {"buffers", "images"}) {
        auto list = doc.find(array);
        if (list == doc.end() || !list->is_array()) continue;
        for (const auto& item : *list) {
            auto uri = item.is_object() ? item.find("uri") : item.end();
            if (uri == item.end() || !uri->is_string()) continue;
            std::string text = uri->get<std::string>();
            if (!text.empty() && text[0] == '/' && !allowAnyPath())
                throwInputError(label, "",
                                "refusing to read \"" + elideUri(text) +
                                    "\": it is outside the model's folder (--allow-any-path reads it)");
        }
    }
    return checkGltfExtensions(doc, label);
}

tinygltf::FsCallbacks confinedFsCallbacks(GltfFileAccess& access) {
    return {confinedFileExists, keepPath, confinedReadWholeFile, refuseWrite, &access};
}

}  // namespace penumbra
