// The two kinds of failure the command line distinguishes (SCENE_FORMAT.md, exit status):
// InputError = the user's input is bad (exit 2); any other std::exception = exit 1.
// Messages are one line: what was attempted or where, then why.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

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

// Messages never echo an input's contents at length: a word or value quoted from a file
// keeps its first `kept` bytes, and the rest becomes "... (N bytes)", so that a 50 MB word
// costs one short line (and a terminal is not flooded).
inline std::string elide(std::string_view text, size_t kept = 64) {
    if (text.size() <= kept) return std::string(text);
    return std::string(text.substr(0, kept)) + "... (" + std::to_string(text.size()) + " bytes)";
}

// A URI as messages quote it: a file path whole (up to PATH_MAX, 4096 bytes), a `data:`
// URI, which holds the file's contents, as its first 64 bytes.
inline std::string elideUri(std::string_view uri) {
    return elide(uri, uri.find("data:") != std::string_view::npos ? 64 : 4096);
}

// The same for every word (run of non-blank bytes) of a library's message, which may quote
// what it failed on (tinygltf quotes a whole data: URI that does not decode).
inline std::string elideWords(std::string_view text) {
    std::string out;
    size_t i = 0;
    while (i < text.size()) {
        size_t end = text.find_first_of(" \t", i);
        if (end == std::string_view::npos) end = text.size();
        out += elideUri(text.substr(i, end - i));
        if (end < text.size()) out += text[end];
        i = end + 1;
    }
    return out;
}

}  // namespace penumbra
