// Output formats by extension (see output_format.h).
#include "image/output_format.h"

#include <algorithm>
#include <cctype>

namespace penumbra {

namespace fs = std::filesystem;

std::optional<OutputFormat> outputFormatOf(const fs::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".exr") return OutputFormat::Exr;
    if (ext == ".png") return OutputFormat::Png;
    // Devices and pipes are written through in place (atomic_file.h); their names are the
    // system's, not the user's choice of format.
    std::error_code ec;
    const fs::file_type type = fs::status(path, ec).type();
    if (!ec && (type == fs::file_type::character || type == fs::file_type::fifo)) return OutputFormat::Exr;
    return std::nullopt;
}

std::string outputFormatProblem(const fs::path& path) {
    return "\"" + path.string() + "\" does not end in .exr or .png (the output format is told by the extension)";
}

}  // namespace penumbra
