// glTF extensions: supported, required, ignored (gltf_extensions.h).
#include "scene/gltf_extensions.h"

#include <algorithm>

#include "core/errors.h"

namespace penumbra {

const std::vector<std::string>& supportedGltfExtensions() {
    static const std::vector<std::string> names = {"KHR_lights_punctual", "KHR_materials_emissive_strength",
                                                   "KHR_texture_transform"};
    return names;
}

namespace {

bool supported(const std::string& name) {
    const auto& names = supportedGltfExtensions();
    return std::find(names.begin(), names.end(), name) != names.end();
}

// Names are the file's own: a long one is cut, so that a message stays one short line.
std::string shown(const std::string& name) { return name.size() > 64 ? name.substr(0, 61) + "..." : name; }

std::string joined(const std::vector<std::string>& names, const char* last) {
    std::string out;
    for (size_t i = 0; i < names.size(); ++i) {
        if (i > 0) out += i + 1 == names.size() ? last : ", ";
        out += names[i];
    }
    return out;
}

}  // namespace

std::vector<std::string> checkGltfExtensions(const nlohmann::json& doc, const std::string& label) {
    auto required = doc.find("extensionsRequired");
    if (required != doc.end()) {
        if (!required->is_array()) throwInputError(label, "extensionsRequired", "expected an array of names");
        for (size_t i = 0; i < required->size(); ++i) {
            const auto& name = (*required)[i];
            std::string path = "extensionsRequired[" + std::to_string(i) + "]";
            if (!name.is_string()) throwInputError(label, path, "expected an extension name");
            if (!supported(name.get<std::string>()))
                throwInputError(label, path,
                                "unsupported required extension \"" + shown(name.get<std::string>()) +
                                    "\" (Penumbra reads " + joined(supportedGltfExtensions(), " and ") + ")");
        }
    }
    std::vector<std::string> ignored;
    auto used = doc.find("extensionsUsed");
    if (used == doc.end() || !used->is_array()) return ignored;
    for (const auto& name : *used) {
        if (!name.is_string()) continue;
        std::string text = shown(name.get<std::string>());
        if (!supported(text) && std::find(ignored.begin(), ignored.end(), text) == ignored.end() && ignored.size() < 16)
            ignored.push_back(text);
    }
    return ignored;
}

std::string ignoredGltfExtensionsNote(const std::vector<std::string>& ignored) {
    if (ignored.empty()) return "";
    return std::string("ignoring optional extension") + (ignored.size() > 1 ? "s " : " ") + joined(ignored, ", ") +
           " (the model renders without " + (ignored.size() > 1 ? "them)" : "it)");
}

}  // namespace penumbra
