// Reads one entry of a scene's `materials` object (SCENE_FORMAT.md, "Materials") into a
// Material: one function per material kind in material_parse.cpp, each with its keys,
// defaults and ranges. A new kind adds its function there and its name to the choice.
#pragma once

#include <string>

#include "scene/json_reader.h"
#include "scene/material_textures.h"
#include "scene/scene.h"

namespace penumbra {

// `m` is the material's object, `name` its key; fields written as texture objects are read
// by `textures`. Throws InputError naming the file and the JSON path of the offending value.
Material parseMaterial(const JsonReader& m, const std::string& name, MaterialTextureReader& textures);

}  // namespace penumbra
