// The checks every scene-relative input file passes (see scene_input_file.h), written once
// so that their messages stay the same for every kind of file.
#include "scene/scene_input_file.h"

#include <string>

#include "core/input_file.h"

namespace penumbra {

namespace fs = std::filesystem;

fs::path sceneRelativeInputFile(const JsonReader& field, const fs::path& baseDir, bool confined) {
    std::string name = field.string();
    fs::path file = baseDir / name;
    if (auto problem = openProblem(file)) field.fail("cannot open \"" + file.string() + "\" (" + *problem + ")");
    if (confined && !allowAnyPath() && !isInsideFolder(file, baseDir))
        field.fail("refusing to read \"" + name + "\": it is outside the scene's folder (--allow-any-path reads it)");
    return file;
}

}  // namespace penumbra
