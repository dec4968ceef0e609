// Files that a scene names (environment maps, material textures, glTF shapes): resolved
// against the scene's folder and checked before anything reads them. The rules themselves
// (errno's words, what "inside" means) are core/input_file's.
#pragma once

#include <filesystem>

#include "scene/json_reader.h"

namespace penumbra {

// `baseDir / field.string()`, once it can be opened and, when `confined` and any path is
// not allowed, lies inside `baseDir` (docs/design/contract-decisions.md, "glTF file access"). Fails on `field` with
// "cannot open \"FILE\" (why)" or "refusing to read \"NAME\": it is outside the scene's
// folder (--allow-any-path reads it)". `confined` is false only for a model given on the
// command line, which is the user's own choice.
std::filesystem::path sceneRelativeInputFile(const JsonReader& field, const std::filesystem::path& baseDir,
                                             bool confined = true);

}  // namespace penumbra
