// Writing an output file so that it is either complete or absent (SCENE_FORMAT.md: a
// failed or interrupted render never leaves a truncated image behind). The format
// writers (exr.cpp, png.cpp) supply the bytes; this file owns the temporary and rename.
#pragma once

#include <filesystem>
#include <functional>

namespace penumbra {

// Calls `write(tmp)` with a fresh temporary path beside `target` (same directory, so
// the rename cannot cross file systems), then renames it over `target`. On any failure
// the temporary is removed and std::runtime_error("failed to write TARGET: why") thrown.
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path& tmp)>& write);

}  // namespace penumbra
