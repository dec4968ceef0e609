// Output checks before rendering (see output_check.h): the same rules for render, batch,
// merge and preview, so that no output is found unwritable after the work, and no run
// overwrites its own scene or writes one file twice.
#include "image/output_check.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <stdexcept>
#include <unordered_map>

#include "core/errors.h"
#include "image/atomic_file.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

// fileIdentity, with the directories of files still to be created resolved once each: a
// sweep of a million outputs into one folder costs a million stat calls, not ten.
class IdentityCache {
public:
    std::string identity(const fs::path& path) {
        struct stat st {};
        if (::stat(path.c_str(), &st) == 0)
            return "inode " + std::to_string(uint64_t(st.st_dev)) + ":" + std::to_string(uint64_t(st.st_ino));
        // A file still to be created: a dangling symlink creates the file it names.
        fs::path target = path;
        try {
            target = finalTarget(path);
        } catch (const std::exception&) {
            // a loop: it cannot be written anyway (checkWritable says so); compare the spelling
        }
        std::error_code ec;
        const fs::path absolute = fs::absolute(target, ec);
        const fs::path name = absolute.filename();
        if (ec || name.empty() || name == "." || name == "..") return "path " + resolve(absolute).string();
        auto [it, fresh] = m_dirs.try_emplace(absolute.parent_path().string());
        if (fresh) it->second = resolve(absolute.parent_path());
        return "path " + (it->second / name).string();
    }

private:
    // Symlinks of the existing prefix resolved, then "." and ".." removed.
    static fs::path resolve(const fs::path& path) {
        std::error_code ec;
        fs::path resolved = fs::weakly_canonical(path, ec);
        return ec ? path.lexically_normal() : resolved;
    }

    std::unordered_map<std::string, fs::path> m_dirs;
};

}  // namespace

std::string fileIdentity(const fs::path& path) { return IdentityCache().identity(path); }

void checkDistinctFiles(const std::vector<RunFile>& outputs, const std::vector<RunFile>& inputs,
                        const std::string& prefix) {
    IdentityCache cache;
    std::unordered_map<std::string, const RunFile*> seen;  // identity -> first input with it
    seen.reserve(inputs.size());
    for (const RunFile& in : inputs) seen.emplace(cache.identity(in.path), &in);
    auto refuse = [&](const RunFile& out, const RunFile& other, const char* kind) {
        throw InputError(prefix + out.role + " \"" + out.path.string() + "\" is the same file as " + other.role +
                         " \"" + other.path.string() + "\"; " + kind);
    };
    std::unordered_map<std::string, const RunFile*> written;
    written.reserve(outputs.size());
    for (const RunFile& out : outputs) {
        const std::string id = cache.identity(out.path);
        if (auto it = seen.find(id); it != seen.end())
            refuse(out, *it->second, "an output must not overwrite an input");
        // A character device (/dev/null) is written through, never replaced (atomic_file.h):
        // two outputs sent to it clobber nothing, so `-o /dev/null --png /dev/null` is fine.
        std::error_code ec;
        if (fs::is_character_file(out.path, ec)) continue;
        auto [it, fresh] = written.emplace(id, &out);
        if (!fresh) refuse(out, *it->second, "every output must be a file of its own");
    }
}

void checkWritable(const fs::path& output, bool createDirectory) {
    const std::string prefix = "cannot write " + output.string() + ": ";
    std::error_code ec;
    const fs::file_status status = fs::status(output, ec);  // follows symlinks
    if (ec && status.type() != fs::file_type::not_found) throw std::runtime_error(prefix + ec.message());
    switch (status.type()) {
        case fs::file_type::directory: throw std::runtime_error(prefix + "it is a directory");
        case fs::file_type::character:
        case fs::file_type::fifo:
            // Written in place (atomic_file.h): the file itself must be writable.
            if (::access(output.c_str(), W_OK) != 0) throw std::runtime_error(prefix + std::strerror(errno));
            return;
        case fs::file_type::regular:
        case fs::file_type::not_found: break;
        default:
            throw std::runtime_error(prefix + "not a regular file, character device or FIFO (" +
                                     (status.type() == fs::file_type::block ? "a block device" : "a socket") + ")");
    }
    // A new or regular file is replaced by a rename in the directory of the file the path
    // leads to (through a symlink, the link's target's directory).
    fs::path dir;
    try {
        dir = finalTarget(output).parent_path();
    } catch (const std::exception&) {
        throw std::runtime_error(prefix + "too many levels of symbolic links");
    }
    if (dir.empty()) dir = ".";
    if (createDirectory) {
        fs::create_directories(dir, ec);
        if (ec) throw std::runtime_error(prefix + "cannot create " + dir.string() + " (" + ec.message() + ")");
    }
    if (!fs::exists(dir, ec)) throw std::runtime_error(prefix + "directory " + dir.string() + " does not exist");
    if (!fs::is_directory(dir, ec)) throw std::runtime_error(prefix + dir.string() + " is not a directory");
    if (::access(dir.c_str(), W_OK) != 0)
        throw std::runtime_error(prefix + "directory " + dir.string() + " is not writable");
    // The write goes through a temporary with a longer name (atomic_file.h): a name that
    // fits but whose temporary does not would fail only after the render.
    long nameMax = ::pathconf(dir.c_str(), _PC_NAME_MAX);
    if (nameMax <= 0) nameMax = 255;
    const size_t name = finalTarget(output).filename().string().size(), suffix = longestTemporaryName(output) - name;
    if (name + suffix > size_t(nameMax))
        throw std::runtime_error(prefix + "file name too long (" + std::to_string(name) + " bytes; at most " +
                                 std::to_string(size_t(nameMax) > suffix ? size_t(nameMax) - suffix : 0) +
                                 " here, leaving room for the temporary file's suffix)");
}

void checkOutputs(const std::vector<RunFile>& outputs, const std::vector<RunFile>& inputs, bool createDirectories) {
    checkDistinctFiles(outputs, inputs);
    for (const RunFile& out : outputs) checkWritable(out.path, createDirectories);
}

}  // namespace penumbra
