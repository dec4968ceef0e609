// Temporary-then-rename writing for output images (see atomic_file.h). The temporary's
// name carries the process id and a counter, so concurrent writers never share one.
#include "image/atomic_file.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <string>

namespace penumbra {

namespace {

// Library messages (OpenEXR's among them) may span lines; ours are one line.
std::string oneLine(std::string text) {
    std::replace(text.begin(), text.end(), '\n', ' ');
    std::replace(text.begin(), text.end(), '\r', ' ');
    return text;
}

}  // namespace

void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path& tmp)>& write) {
    namespace fs = std::filesystem;
    static std::atomic<unsigned> counter{0};
    const std::string prefix = "failed to write " + target.string() + ": ";

    // Checked up front so the message names the user's directory, not our temporary.
    const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw std::runtime_error(prefix + "directory " + dir.string() + " does not exist");
    if (fs::is_directory(target, ec)) throw std::runtime_error(prefix + "it is a directory");

    fs::path tmp = target;
    tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    try {
        write(tmp);
        fs::rename(tmp, target);
    } catch (const std::exception& e) {
        fs::remove(tmp, ec);  // best effort; the original failure is the one to report
        throw std::runtime_error(prefix + oneLine(e.what()));
    } catch (...) {
        fs::remove(tmp, ec);
        throw std::runtime_error(prefix + "unknown error");
    }
}

}  // namespace penumbra
