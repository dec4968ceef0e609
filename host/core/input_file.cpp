// Bounded reads of input files with the system's own words for failures, and the rule
// that a file named by another file lies inside the naming file's folder.
#include "core/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstring>

#include "core/errors.h"
#include "core/stop_request.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

std::atomic<bool> g_allowAnyPath{false};

// "No such file or directory" -> "no such file"; others as strerror words, lower case.
std::string describeErrno(int errnum) {
    if (errnum == ENOENT) return "no such file";
    if (errnum == EISDIR) return "it is a directory";
    std::string text = std::strerror(errnum);
    if (!text.empty()) text[0] = char(std::tolower((unsigned char)text[0]));
    return text;
}

// What kind of file that is not a regular one `mode` says, for the refusal.
std::string kindOf(mode_t mode) {
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

std::string notRegular(mode_t mode) { return "cannot open file (not a regular file: " + kindOf(mode) + ")"; }

// Closes the descriptor on every way out of readInputFile.
struct FileDescriptor {
    int fd;
    ~FileDescriptor() {
        if (fd >= 0) ::close(fd);
    }
};

}  // namespace

std::optional<std::string> openProblem(const fs::path& file) {
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0) return describeErrno(errno);
    if (S_ISDIR(st.st_mode)) return describeErrno(EISDIR);
    return std::nullopt;
}

void checkRegularFile(const fs::path& file, const std::string& label) {
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0) throwInputError(label, "", "cannot open file (" + describeErrno(errno) + ")");
    if (S_ISDIR(st.st_mode)) throwInputError(label, "", "cannot open file (" + describeErrno(EISDIR) + ")");
    if (!S_ISREG(st.st_mode)) throwInputError(label, "", notRegular(st.st_mode));
}

std::string readInputFile(const fs::path& file, const std::string& label, uint64_t maxBytes) {
    // O_NONBLOCK: opening a FIFO without a writer would otherwise wait forever, deaf to
    // signals (SA_RESTART); for a regular file it changes nothing.
    FileDescriptor in{::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY)};
    if (in.fd < 0) throwInputError(label, "", "cannot open file (" + describeErrno(errno) + ")");
    struct stat st {};
    if (::fstat(in.fd, &st) != 0) throwInputError(label, "", "cannot open file (" + describeErrno(errno) + ")");
    if (S_ISDIR(st.st_mode)) throwInputError(label, "", "cannot open file (" + describeErrno(EISDIR) + ")");
    // FIFOs, devices and sockets may never end or never answer: input files are regular.
    if (!S_ISREG(st.st_mode)) throwInputError(label, "", notRegular(st.st_mode));
    const std::string tooLarge = "file too large (more than " + std::to_string(maxBytes) + " bytes)";
    if (uint64_t(st.st_size) > maxBytes) throwInputError(label, "", tooLarge);

    std::string text;
    text.reserve(size_t(st.st_size));
    char chunk[1 << 16];
    while (true) {
        throwIfStopRequested();  // a 1 GiB file is 16384 chunks: a stop waits one
        ssize_t got = ::read(in.fd, chunk, sizeof chunk);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throwInputError(label, "", "read error: " + describeErrno(errno));
        if (got == 0) break;
        // A file that grows while it is read is still capped.
        if (text.size() + uint64_t(got) > maxBytes) throwInputError(label, "", tooLarge);
        text.append(chunk, size_t(got));
    }
    return text;
}

void setAllowAnyPath(bool allow) { g_allowAnyPath = allow; }
bool allowAnyPath() { return g_allowAnyPath; }

bool isInsideFolder(const fs::path& file, const fs::path& folder) {
    std::error_code ec1, ec2;
    // Absolute first: weakly_canonical leaves a relative path relative when none of it
    // exists yet (an output "a.exr" beside a job file named "jobs.json").
    fs::path f = fs::weakly_canonical(fs::absolute(file, ec1), ec1);
    fs::path d = fs::weakly_canonical(fs::absolute(folder.empty() ? fs::path(".") : folder, ec2), ec2);
    if (ec1 || ec2) return false;
    // Component-wise prefix: /a/bc is not inside /a/b.
    auto fi = f.begin();
    for (auto di = d.begin(); di != d.end(); ++di, ++fi) {
        if (di->empty() && std::next(di) == d.end()) break;  // a trailing separator
        if (fi == f.end() || *fi != *di) return false;
    }
    return true;
}

}  // namespace penumbra
