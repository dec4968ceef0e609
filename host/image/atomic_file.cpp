// Temporary-then-rename writing for output images, and writing through to devices and
// FIFOs (see atomic_file.h). The temporary's name carries the process id and a counter,
// so concurrent writers never share one.
#include "image/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <stdexcept>
#include <string>

namespace penumbra {

namespace fs = std::filesystem;

namespace {

// Library messages (OpenEXR's among them) may span lines; ours are one line.
std::string oneLine(std::string text) {
    std::replace(text.begin(), text.end(), '\n', ' ');
    std::replace(text.begin(), text.end(), '\r', ' ');
    return text;
}

// Linux's own limit on symlinks followed in one lookup (MAXSYMLINKS).
constexpr int kMaxSymlinks = 40;

// Writes all of `bytes` to the open descriptor; false (errno set) on failure.
bool writeAll(int fd, std::string_view bytes) {
    while (!bytes.empty()) {
        ssize_t n = ::write(fd, bytes.data(), bytes.size());
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        bytes.remove_prefix(size_t(n));
    }
    return true;
}

// Opens `target` for writing in place if it is a character device or FIFO: -1 (errno 0)
// when it is something else, -1 (errno set) when it cannot be opened.
int openStream(const fs::path& target) {
    // O_NONBLOCK: opening a FIFO without a reader fails (ENXIO) instead of waiting forever.
    int fd = ::open(target.c_str(), O_WRONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) return -1;
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !(S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode))) {
        ::close(fd);
        errno = 0;
        return -1;
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);  // now block while the reader catches up
    return fd;
}

// The temporaries of writeFileAtomically for `target` ("NAME.tmp-PID-N") that a process
// which no longer runs left behind (killed with SIGKILL, or the machine went down while
// writing): removed when the same output is written again, so that none stays forever.
// Another live process's (or our own) are in use and stay.
void removeStaleTemporaries(const fs::path& target) {
    const std::string prefix = target.filename().string() + ".tmp-";
    const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
        // PID-N: digits, a dash, digits, nothing else.
        const std::string rest = name.substr(prefix.size());
        const size_t dash = rest.find('-');
        if (dash == 0 || dash == std::string::npos || dash > 9 || dash + 1 == rest.size() ||
            rest.find_first_not_of("0123456789-") != std::string::npos || rest.find('-', dash + 1) != std::string::npos)
            continue;
        const pid_t pid = pid_t(std::stol(rest.substr(0, dash)));
        if (pid == ::getpid() || !(::kill(pid, 0) != 0 && errno == ESRCH)) continue;
        std::error_code removeError;
        if (it->is_regular_file(removeError)) fs::remove(it->path(), removeError);
    }
}

}  // namespace

fs::path finalTarget(const fs::path& path) {
    fs::path p = path;
    for (int i = 0; i < kMaxSymlinks; ++i) {
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
        fs::path next = fs::read_symlink(p, ec);
        if (ec) return p;
        p = next.is_absolute() ? next : p.parent_path() / next;
    }
    throw std::runtime_error("cannot write " + path.string() + ": too many levels of symbolic links");
}

bool isStreamOutput(const fs::path& path) {
    std::error_code ec;
    fs::file_status s = fs::status(path, ec);  // follows symlinks, /dev/stdout's included
    return !ec && (s.type() == fs::file_type::character || s.type() == fs::file_type::fifo);
}

size_t longestTemporaryName(const fs::path& target) {
    constexpr size_t kSuffix = std::string_view(".tmp-").size() + 10 + 1 + 10;
    return finalTarget(target).filename().string().size() + kSuffix;
}

void writeFileAtomically(const fs::path& requested, const std::function<void(const fs::path& tmp)>& write) {
    static std::atomic<unsigned> counter{0};
    const std::string prefix = "failed to write " + requested.string() + ": ";
    fs::path target;
    try {
        target = finalTarget(requested);
    } catch (const std::exception& e) {
        throw std::runtime_error(prefix + "too many levels of symbolic links");
    }

    // Checked up front so the message names the user's directory, not our temporary.
    const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw std::runtime_error(prefix + "directory " + dir.string() + " does not exist");
    const fs::file_status existing = fs::status(target, ec);
    if (fs::is_directory(existing)) throw std::runtime_error(prefix + "it is a directory");
    const bool replacing = fs::is_regular_file(existing);
    if (fs::exists(existing) && !replacing)
        throw std::runtime_error(prefix + "not a regular file (only those are replaced atomically)");

    removeStaleTemporaries(target);
    fs::path tmp = target;
    tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    try {
        write(tmp);
        // A replaced file keeps its permissions (the temporary got the umask's).
        if (replacing) fs::permissions(tmp, existing.permissions(), ec);
        fs::rename(tmp, target);
    } catch (const std::exception& e) {
        fs::remove(tmp, ec);  // best effort; the original failure is the one to report
        throw std::runtime_error(prefix + oneLine(e.what()));
    } catch (...) {
        fs::remove(tmp, ec);
        throw std::runtime_error(prefix + "unknown error");
    }
}

void writeOutputFile(const fs::path& target, std::string_view bytes) {
    if (isStreamOutput(target)) {
        const std::string prefix = "failed to write " + target.string() + ": ";
        int fd = openStream(target);
        if (fd < 0 && errno == ENXIO) throw std::runtime_error(prefix + "no process is reading the FIFO");
        if (fd < 0 && errno != 0) throw std::runtime_error(prefix + std::strerror(errno));
        if (fd >= 0) {
            // A reader that goes away must fail the write, not kill the process.
            auto previous = std::signal(SIGPIPE, SIG_IGN);
            const bool ok = writeAll(fd, bytes);
            const int error = errno;
            std::signal(SIGPIPE, previous);
            if (::close(fd) != 0 && ok) throw std::runtime_error(prefix + std::strerror(errno));
            if (!ok) throw std::runtime_error(prefix + std::strerror(error));
            return;
        }
        // Replaced by a regular file since the check: write that one atomically.
    }
    // Through open/write/close, whose errno says why a write failed (a full disk: "No
    // space left on device"), which std::ofstream does not.
    writeFileAtomically(target, [&](const fs::path& tmp) {
        int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0) throw std::runtime_error("cannot create " + tmp.string() + ": " + std::strerror(errno));
        const bool ok = writeAll(fd, bytes);
        const int error = errno;
        if (::close(fd) != 0 && ok) throw std::runtime_error(std::string("write error: ") + std::strerror(errno));
        if (!ok) throw std::runtime_error(std::string("write error: ") + std::strerror(error));
    });
}

}  // namespace penumbra
