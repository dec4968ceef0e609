// Which image format an output is written in, told by its name (SCENE_FORMAT.md "Output"):
// `.exr` is OpenEXR, `.png` an 8-bit sRGB PNG alone. One rule for `render -o` and batch.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace penumbra {

enum class OutputFormat { Exr, Png };

// The format `path`'s extension names (case-insensitive), or nullopt for any other name,
// which callers refuse (exit 2). A character device or FIFO that exists (/dev/null, a
// pipe) has no format in its name and is written as EXR unless it ends in .png.
std::optional<OutputFormat> outputFormatOf(const std::filesystem::path& path);

// The one-line reason a name is refused, for the caller's message: "\"out.jpg\" does not
// end in .exr or .png (the output format is told by the extension)".
std::string outputFormatProblem(const std::filesystem::path& path);

}  // namespace penumbra
