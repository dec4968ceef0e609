// The input rules for glTF files (docs/design/contract-decisions.md),
// applied around tinygltf: what is checked on the file's JSON before tinygltf sees it, and
// the file callbacks that keep buffer and image reads inside the model's folder.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <tiny_gltf.h>

namespace penumbra {

// The JSON chunk of a .glb file; throws InputError for a container version other than 2
// or a chunk that does not fit the file.
std::string_view glbJsonChunk(const std::string& bytes, const std::string& label);

// Parses the glTF JSON with the rules every JSON reader shares (depth, duplicate keys, no
// echo), then requires asset.version 2.x, whole numbers in integer properties, and no
// absolute buffer or image URI unless any path is allowed, and no required extension the
// reader lacks (gltf_extensions.h). Throws InputError. Returns the names of the optional
// extensions the file uses that are ignored, for a note.
std::vector<std::string> checkGltfDocument(std::string_view json, const std::string& label);

// What the file callbacks saw: the first URI refused and the first read that failed (as
// messages for the caller to throw once tinygltf returns).
struct GltfFileAccess {
    std::filesystem::path folder;  // the model's folder; URIs are read only inside it
    std::string refused;           // the URI as written (relative to the folder)
    std::string failed;            // an InputError message
};

// tinygltf file callbacks reading through readInputFile, only inside access.folder
// unless allowAnyPath(); never expanding a path (tinygltf's own runs wordexp); never writing.
tinygltf::FsCallbacks confinedFsCallbacks(GltfFileAccess& access);

}  // namespace penumbra
