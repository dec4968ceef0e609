// Writing an output file so that it is either complete or absent (SCENE_FORMAT.md: a
// failed or interrupted render never leaves a truncated image behind). The format
// writers (exr.cpp, png.cpp) supply the bytes; this file owns where they go: a temporary
// and a rename for regular files (through symlinks, which stay), straight through for
// character devices and FIFOs, which cannot be replaced.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string_view>

namespace penumbra {

// The file a write to `path` lands in: `path` with symlinks in its last component
// followed (a dangling link leads to the file it names). Throws std::runtime_error on a
// symlink loop.
std::filesystem::path finalTarget(const std::filesystem::path& path);

// True when `path` is (or leads to) a character device (e.g. /dev/null) or a FIFO: such
// outputs are opened and written in place, since renaming over them would replace them.
bool isStreamOutput(const std::filesystem::path& path);

// The longest name writeFileAtomically gives the temporary of `target`: the final
// target's file name and ".tmp-PID-N" (PID and N at most 10 digits each). Output checks
// refuse a name whose temporary would not fit, before rendering (output_check.h).
size_t longestTemporaryName(const std::filesystem::path& target);

// Calls `write(tmp)` with a fresh temporary path beside finalTarget(requested) (same
// directory, so the rename cannot cross file systems), then renames it over that file:
// a symlink keeps pointing at the new file, and a replaced file keeps its permissions.
// On any failure the temporary is removed and std::runtime_error("failed to write
// REQUESTED: why") thrown. An existing target that is not a regular file is refused.
void writeFileAtomically(const std::filesystem::path& requested,
                         const std::function<void(const std::filesystem::path& tmp)>& write);

// Writes `bytes` to `target`: atomically as above, or straight into a character device or
// FIFO (a FIFO must have a reader: no waiting for one). Failures as above.
void writeOutputFile(const std::filesystem::path& target, std::string_view bytes);

}  // namespace penumbra
