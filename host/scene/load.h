// Loading scenes: JSON scene files (SCENE_FORMAT.md) and glTF 2.0 files rendered directly.
// Every problem with the input throws InputError naming the file and the JSON path (or the
// line and column of a JSON syntax error); nothing is written before loading succeeds.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace penumbra {

// One `--set PATH=VALUE` (the shorthands --spp/--seed/--width/--height become these too).
struct Override {
    std::string path;   // dotted JSON path with [i] indices, e.g. "lights[0].power"
    std::string value;  // parsed as JSON, falling back to a plain string
};

// Splits "PATH=VALUE" at the first '='; throws InputError("--set ...: ...") when malformed.
Override parseOverride(const std::string& text);

// Sets `doc` at `override.path` to the override's value, creating missing objects on the
// way (and appending when an index equals the array's size). Throws InputError.
void applyOverride(nlohmann::json& doc, const Override& override);
// The same with a value that is JSON already (the Python module's `set=`); `override.value`
// only names it in messages.
void applyOverrideValue(nlohmann::json& doc, const Override& override, nlohmann::json value);

// Reads and parses a JSON file; InputError names `label` and, for a syntax error, the line
// and column (shared by scene files and penumbra batch job files).
nlohmann::json readJsonFile(const std::filesystem::path& file, const std::string& label);

// A scene document before validation, with what its messages and files are relative to.
struct SceneDocument {
    nlohmann::json doc;
    std::string label;              // names the scene in messages: the file as given
    std::filesystem::path baseDir;  // files the scene names are relative to (and inside)
    std::string name;               // the file's stem (Scene::name)
    bool modelAlone = false;        // a glTF model given on its own (see loadScene)
};

// The document of `file`: *.json read as a scene file, *.gltf / *.glb wrapped in the scene
// document {"shapes": [{"type": "gltf", "file": ...}]}, so that overrides work on it
// exactly as on a scene file. Throws InputError.
SceneDocument readSceneDocument(const std::filesystem::path& file);
// Validates `document` and converts it into a Scene (SCENE_FORMAT.md); throws InputError.
Scene buildScene(const SceneDocument& document);

// Loads a scene: *.json as a scene file, *.gltf / *.glb as a glTF model rendered on its
// own (SCENE_FORMAT.md "glTF input"). Overrides are applied to the JSON document before
// validation (for glTF input, to the scene document that wraps the model).
Scene loadScene(const std::filesystem::path& file, const std::vector<Override>& overrides = {});

}  // namespace penumbra
