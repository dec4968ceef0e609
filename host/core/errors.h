// The two kinds of failure the command line distinguishes (SCENE_FORMAT.md, exit status):
// InputError = the user's input is bad (exit 2); any other std::exception = exit 1.
// Messages are one line: what was attempted or where, then why.
#pragma once

#include <stdexcept>
#include <string>

namespace penumbra {

// Bad usage or bad input: a scene, glTF or image file that is missing, unreadable or
// invalid. The message names the file and, for scene files, the JSON path, e.g.
//   cornell.json: shapes[3].material: unknown material "flor"
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Throws InputError("<file>: <jsonPath>: <message>") (the path part omitted when empty).
[[noreturn]] inline void throwInputError(const std::string& file, const std::string& jsonPath,
                                         const std::string& message) {
    std::string text = file;
    if (!jsonPath.empty()) text += ": " + jsonPath;
    throw InputError(text + ": " + message);
}

}  // namespace penumbra
