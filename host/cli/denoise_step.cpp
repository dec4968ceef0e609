// The Python denoiser as a child process (see denoise_step.h).
#include "cli/denoise_step.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/errors.h"

namespace penumbra {
namespace {

constexpr const char* kInstall =
    "install the Python module with pyoidn (pip install penumbra[denoise]; docs/guide/python.md)";

std::string python() {
    const char* chosen = std::getenv("PENUMBRA_PYTHON");
    return chosen && *chosen ? chosen : "python3";
}

struct Outcome {
    bool started = false;
    int status = -1;         // the exit status, or -1 when killed by a signal
    std::string stderrText;  // what it wrote on stderr
};

// Runs PYTHON -m penumbra.denoise_exr ARGS..., its stdout inherited and its stderr captured.
Outcome runDenoiser(const std::vector<std::string>& args) {
    std::vector<std::string> words{python(), "-m", "penumbra.denoise_exr"};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);

    Outcome outcome;
    int pipeFds[2];
    if (pipe(pipeFds) != 0) throw std::runtime_error(std::string("--denoise: pipe: ") + std::strerror(errno));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDERR_FILENO);
    posix_spawn_file_actions_addclose(&actions, pipeFds[0]);
    pid_t pid = 0;
    const int spawned = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(pipeFds[1]);
    if (spawned == 0) {
        outcome.started = true;
        char buffer[4096];
        for (ssize_t n; (n = read(pipeFds[0], buffer, sizeof buffer)) != 0;) {
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) break;
            if (outcome.stderrText.size() < (1u << 20)) outcome.stderrText.append(buffer, size_t(n));
        }
        int status = 0;
        while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
        outcome.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    close(pipeFds[0]);
    return outcome;
}

// The child's last non-empty stderr line (a traceback's last line is the error itself).
std::string lastLine(const std::string& text) {
    size_t end = text.find_last_not_of("\r\n \t");
    if (end == std::string::npos) return "";
    const size_t newline = text.rfind('\n', end);
    const size_t start = newline == std::string::npos ? 0 : newline + 1;
    return elide(text.substr(start, end - start + 1), 300);
}

}  // namespace

void checkDenoiser() {
    const Outcome outcome = runDenoiser({"--check"});
    if (!outcome.started)
        throw InputError("--denoise: no " + python() + " to run the denoiser ($PENUMBRA_PYTHON or python3 on PATH); " +
                         kInstall);
    if (outcome.status == 0) return;
    const std::string why = lastLine(outcome.stderrText);
    // pyoidn missing: denoise_exr's own line already says how to install it.
    if (why.find("needs pyoidn") != std::string::npos) throw InputError("--denoise: " + why);
    throw InputError("--denoise: " + python() + " cannot run penumbra.denoise_exr (" + why + "); " + kInstall);
}

void denoiseExr(const std::filesystem::path& noisy, const std::filesystem::path& output) {
    const Outcome outcome = runDenoiser({noisy.string(), output.string()});
    if (!outcome.started || outcome.status != 0)
        throw std::runtime_error("--denoise: " + output.string() + " not written: " +
                                 (outcome.started ? lastLine(outcome.stderrText) : "no " + python()));
}

}  // namespace penumbra
