// Which glTF extensions Penumbra reads, and what it does with the others (glTF 2.0 §3.12):
// a file that *requires* one it does not read is refused, naming the extension, before
// tinygltf parses it (a compressed mesh would otherwise fail as an unexplained broken
// accessor); one that is only *used* is ignored with a one-line note, as viewers do.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace penumbra {

// The extensions the glTF reader implements (load_gltf.cpp): the one list every check reads.
const std::vector<std::string>& supportedGltfExtensions();

// Throws InputError "<label>: extensionsRequired[i]: unsupported required extension
// \"NAME\" (...)" for the first required extension not supported; returns the names in
// extensionsUsed that are not supported (document order, each once), for a note.
std::vector<std::string> checkGltfExtensions(const nlohmann::json& doc, const std::string& label);

// The note for ignored optional extensions, or "" when there are none.
std::string ignoredGltfExtensionsNote(const std::vector<std::string>& ignored);

}  // namespace penumbra
