// Reading input files (scenes, job files, glTF models, the files a model names, image
// files) under Penumbra's input rules: a size cap per kind of file, errno's words for what
// went wrong, and, unless any path is allowed, only files inside the folder of the file
// naming them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace penumbra {

// Scene and job files: JSON, 1 GiB at most (a 5M-triangle mesh written out is ~300 MB).
constexpr uint64_t kMaxJsonFileBytes = uint64_t(1) << 30;
// glTF models (.gltf/.glb) and each buffer they name: 2 GiB at most (tinygltf sizes are 32-bit).
constexpr uint64_t kMaxModelFileBytes = uint64_t(1) << 31;

// The whole file; throws InputError "<label>: cannot open file (<why>)", "<label>: read
// error: <strerror>" or "<label>: file too large (more than N bytes)". Input files must be
// regular files (after symlinks): a FIFO, device or socket is refused as "cannot open file
// (not a regular file: a FIFO)", without waiting for a writer, since one may never come
// or never end. Throws Stopped (core/stop_request.h) when a stop is asked for meanwhile.
std::string readInputFile(const std::filesystem::path& file, const std::string& label, uint64_t maxBytes);
// The same refusals for a reader that opens the file itself (OpenEXR's): missing,
// a directory, or not a regular file.
void checkRegularFile(const std::filesystem::path& file, const std::string& label);

// Why `file` cannot be opened ("no such file", "too many levels of symbolic links", "it
// is a directory"), or nothing when it can be.
std::optional<std::string> openProblem(const std::filesystem::path& file);

// Files that a scene or a glTF model names (glTF shapes, buffer and image URIs) are read
// only from inside the naming file's folder, after resolving symlinks and "..", unless
// this process allows any path (`--allow-any-path`, for trusted files).
void setAllowAnyPath(bool allow);
bool allowAnyPath();
// Whether `file` resolves to a place inside `folder` (resolved too).
bool isInsideFolder(const std::filesystem::path& file, const std::filesystem::path& folder);

}  // namespace penumbra
