// The Slurm launchers of tools/slurm/ on a real, throwaway Slurm cluster of one node:
// munged, slurmctld and slurmd started as root from a generated configuration in a
// temporary directory, a batch job array and a split render with its dependent merge
// submitted through the scripts, and the daemons stopped again whatever happens.
// Skips (never passes) where it cannot run: not root, or slurm-wlm / munge not installed
// (tools/setup installs them), or the daemons do not come up in this environment.
#include <arpa/inet.h>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <netinet/in.h>
#include <regex>
#include <sys/socket.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_fixture.h"
#include "image/image.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// stdout of a shell command (stderr to stderr); empty on failure.
std::string capture(const std::string& command, int* status = nullptr) {
    std::string out;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return out;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
    int raw = pclose(pipe);
    if (status) *status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return out;
}

bool haveCommand(const std::string& name) {
    return std::system(("command -v " + name + " >/dev/null 2>&1").c_str()) == 0;
}

std::string slurp(const fs::path& path, size_t tail = 4000) {
    std::ifstream in(path);
    std::string text(std::istreambuf_iterator<char>(in), {});
    return text.size() > tail ? text.substr(text.size() - tail) : text;
}

// A TCP port on 127.0.0.1 that was free a moment ago.
int freePort() {
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof addr;
    int port = -1;
    if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
        getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0)
        port = ntohs(addr.sin_port);
    close(fd);
    return port;
}

// Polls `done` every 200 ms until it holds or `seconds` pass.
bool waitFor(double seconds, const std::function<bool()>& done) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
    while (!done()) {
        if (Clock::now() > deadline) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    return true;
}

// One-node Slurm cluster. The constructor starts the daemons (foreground processes this
// test owns); the destructor cancels the cluster's jobs and stops them, in every case.
class LocalSlurm {
public:
    // Why the cluster cannot run here, or empty.
    static std::string unavailable() {
        if (geteuid() != 0) return "needs root (munged, slurmctld and slurmd run as SlurmUser=root)";
        for (const char* tool : {"munged", "munge", "slurmctld", "slurmd", "sbatch", "sinfo", "squeue", "scancel"})
            if (!haveCommand(tool))
                return std::string(tool) + " not installed (Debian packages slurm-wlm and munge; tools/setup installs them)";
        return {};
    }

    LocalSlurm() {
        char pattern[] = "/tmp/penumbra-slurm-XXXXXX";  // short: the munge socket path has a length limit
        if (!mkdtemp(pattern)) {
            m_error = "mkdtemp failed";
            return;
        }
        m_dir = pattern;
        for (const char* sub : {"munge", "state", "spool", "log"}) fs::create_directories(m_dir / sub);
        fs::permissions(m_dir / "munge", fs::perms::owner_all, fs::perm_options::replace);
        const fs::path key = m_dir / "munge/munge.key", socket = m_dir / "munge/socket";
        std::string keyCommand = haveCommand("mungekey") ? "mungekey -c -k '" + key.string() + "'"
                                                         : "dd if=/dev/urandom of='" + key.string() + "' bs=1024 count=1";
        if (std::system((keyCommand + " >/dev/null 2>&1 && chmod 0400 '" + key.string() + "'").c_str()) != 0) {
            m_error = "could not create a munge key with: " + keyCommand;
            return;
        }
        spawn({"munged", "-F", "--force", "--socket=" + socket.string(), "--key-file=" + key.string(),
               "--pid-file=" + (m_dir / "munge/munged.pid").string(), "--log-file=" + (m_dir / "log/munged.log").string(),
               "--seed-file=" + (m_dir / "munge/seed").string()},
              m_dir / "log/munged.out");
        if (!waitFor(15, [&] { return fs::exists(socket); })) {
            m_error = "munged did not start: " + slurp(m_dir / "log/munged.out") + slurp(m_dir / "log/munged.log");
            return;
        }

        writeConfig(socket);
        setenv("SLURM_CONF", m_conf.c_str(), 1);
        spawn({"slurmctld", "-D", "-f", m_conf.string()}, m_dir / "log/slurmctld.out");
        spawn({"slurmd", "-D", "-N", "localhost", "-f", m_conf.string()}, m_dir / "log/slurmd.out");
        if (!waitFor(60, [&] { return capture("sinfo -h -N -o %T 2>/dev/null").find("idle") != std::string::npos; })) {
            m_error = "the node did not become idle within 60 s: sinfo says \"" + capture("sinfo -h -N -o %T 2>&1") +
                      "\"; " + logs();
            return;
        }
    }

    ~LocalSlurm() {
        if (m_error.empty()) {  // the cluster came up: jobs may still be running
            std::system("scancel --user=root >/dev/null 2>&1");
            waitFor(20, [&] { return queueEmpty(); });
        }
        // Reverse order of start: slurmd, slurmctld, munged.
        for (auto it = m_daemons.rbegin(); it != m_daemons.rend(); ++it) stop(*it);
        unsetenv("SLURM_CONF");
        std::error_code ec;
        if (!m_dir.empty()) fs::remove_all(m_dir, ec);
    }

    LocalSlurm(const LocalSlurm&) = delete;
    LocalSlurm& operator=(const LocalSlurm&) = delete;

    const std::string& error() const { return m_error; }
    bool queueEmpty() const {
        int status = 0;
        std::string out = capture("squeue -h 2>/dev/null", &status);
        return status == 0 && out.find_first_not_of(" \n") == std::string::npos;
    }
    std::string logs() const {
        return "slurmctld: " + slurp(m_dir / "log/slurmctld.log", 1500) + " slurmd: " + slurp(m_dir / "log/slurmd.log", 1500);
    }

private:
    void writeConfig(const fs::path& socket) {
        // CPUs and memory as slurmd detects them here, so that the node is not drained.
        std::string detected = capture("slurmd -C 2>/dev/null");
        std::smatch m;
        std::string cpus = std::regex_search(detected, m, std::regex("CPUs=([0-9]+)"))
                               ? m[1].str()
                               : std::to_string(std::max(1u, std::thread::hardware_concurrency()));
        long memory = std::regex_search(detected, m, std::regex("RealMemory=([0-9]+)")) ? std::stol(m[1]) : 2048;
        m_conf = m_dir / "slurm.conf";
        std::ofstream conf(m_conf);
        const fs::path& d = m_dir;
        conf << "ClusterName=penumbratest\n"
             << "SlurmctldHost=localhost\n"
             << "SlurmctldPort=" << freePort() << "\n"
             << "SlurmdPort=" << freePort() << "\n"
             << "AuthType=auth/munge\nCredType=cred/munge\n"
             << "AuthInfo=socket=" << socket.string() << "\n"
             << "SlurmUser=root\nSlurmdUser=root\n"
             << "StateSaveLocation=" << (d / "state").string() << "\n"
             << "SlurmdSpoolDir=" << (d / "spool").string() << "\n"
             << "SlurmctldPidFile=" << (d / "slurmctld.pid").string() << "\n"
             << "SlurmdPidFile=" << (d / "slurmd.pid").string() << "\n"
             << "SlurmctldLogFile=" << (d / "log/slurmctld.log").string() << "\n"
             << "SlurmdLogFile=" << (d / "log/slurmd.log").string() << "\n"
             << "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n"
             << "SelectType=select/cons_tres\nSelectTypeParameters=CR_Core\n"
             << "ReturnToService=2\nMpiDefault=none\n"
             << "JobCompType=jobcomp/none\nAccountingStorageType=accounting_storage/none\n"
             << "JobAcctGatherType=jobacct_gather/none\n"
             << "SchedulerType=sched/backfill\nSchedulerParameters=sched_interval=1\n"
             << "NodeName=localhost NodeHostname=localhost NodeAddr=127.0.0.1 CPUs=" << cpus
             << " RealMemory=" << std::max(1L, memory / 2) << " State=UNKNOWN\n"
             << "PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP\n";
    }

    void spawn(const std::vector<std::string>& argv, const fs::path& log) {
        pid_t pid = fork();
        if (pid == 0) {
            int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            dup2(fd, STDOUT_FILENO);
            dup2(fd, STDERR_FILENO);
            setpgid(0, 0);  // its own group: stopping it reaches what it forks
            std::vector<char*> args;
            for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
            args.push_back(nullptr);
            execvp(args[0], args.data());
            _exit(127);
        }
        if (pid > 0) m_daemons.push_back(pid);
    }

    static void stop(pid_t pid) {
        kill(pid, SIGTERM);
        int status;
        if (waitFor(15, [&] { return waitpid(pid, &status, WNOHANG) != 0; })) return;
        kill(-pid, SIGKILL);
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
    }

    fs::path m_dir, m_conf;
    std::vector<pid_t> m_daemons;
    std::string m_error;
};

json tinyScene() { return test::floorAndSphereScene({.width = 16, .height = 12, .spp = 4, .sphereLight = true}); }

std::string q(const fs::path& p) {
    std::string quoted = p.string();
    quoted.insert(quoted.begin(), '\'');
    quoted.push_back('\'');
    return quoted;
}

}  // namespace

TEST(Slurm, JobArrayBatchAndSplitRenderWithDependentMerge) {
    if (std::string why = LocalSlurm::unavailable(); !why.empty()) GTEST_SKIP() << "Slurm test not run: " << why;
    fs::path dir = test::outputPath("slurm");
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "scene.json") << tinyScene().dump(2);
    json jobs = {{"jobs",
                  {{{"scene", "scene.json"},
                    {"output", "frames/frame_{i:02}.exr"},
                    {"sweep", {{"path", "camera.eye"}, {"values", {{0, 1, 4}, {1, 1, 4}, {2, 1, 4}, {3, 1, 4}}}}}}}}};
    std::ofstream(dir / "jobs.json") << jobs.dump(2);

    const auto start = Clock::now();
    LocalSlurm slurm;
    if (!slurm.error().empty()) GTEST_SKIP() << "Slurm test not run: the daemons did not start here: " << slurm.error();
    std::fprintf(stderr, "slurm: cluster up in %.1f s\n", std::chrono::duration<double>(Clock::now() - start).count());

    setenv("PENUMBRA", PENUMBRA_EXECUTABLE, 1);
    const std::string tools = std::string(PENUMBRA_SOURCE_DIR) + "/tools/slurm/";
    const std::string logs = " --output=" + q(dir / "slurm-%x-%A_%a.out");
    int status = 0;
    std::string arrayId = capture("cd " + q(dir) + " && " + tools + "submit-batch jobs.json" + logs, &status);
    ASSERT_EQ(status, 0) << arrayId;
    std::string splitIds = capture("cd " + q(dir) + " && " + tools + "submit-split scene.json split/merged.exr --parts 4 " +
                                       "--spp 18" + logs,
                                   &status);
    ASSERT_EQ(status, 0) << splitIds;
    ASSERT_TRUE(std::regex_match(splitIds, std::regex("[0-9]+ [0-9]+\n"))) << splitIds;

    std::vector<fs::path> expected = {dir / "split/merged.exr"};
    for (int i = 0; i < 4; ++i) {
        expected.push_back(dir / ("frames/frame_0" + std::to_string(i) + ".exr"));
        expected.push_back(dir / ("split/merged.parts/part-000" + std::to_string(i) + ".exr"));
    }
    auto allThere = [&] {
        for (const fs::path& p : expected)
            if (!fs::exists(p)) return false;
        return true;
    };
    // Bounded: done when the queue has drained (the merge runs last); then every file must be there.
    bool drained = waitFor(300, [&] { return slurm.queueEmpty(); });
    std::string jobLogs;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().extension() == ".out") jobLogs += entry.path().filename().string() + ": " + slurp(entry.path(), 600);
    ASSERT_TRUE(drained) << "jobs still queued after 300 s: " << capture("squeue 2>&1") << jobLogs;
    ASSERT_TRUE(allThere()) << "missing outputs; job logs: " << jobLogs << " " << slurm.logs();
    std::fprintf(stderr, "slurm: all jobs done %.1f s after start\n",
                 std::chrono::duration<double>(Clock::now() - start).count());

    // The array's outputs are exactly the job file's: a local batch finds them all complete.
    std::string err;
    ASSERT_EQ(test::runPenumbra("batch " + q(dir / "jobs.json"), &err), 0) << err;
    EXPECT_NE(err.find("rendered 0, skipped 4, failed 0"), std::string::npos) << err;

    // Parts: 18 spp in 4 parts is 5, 5, 4, 4 at offsets 0, 5, 10, 14.
    const int spp[] = {5, 5, 4, 4}, offset[] = {0, 5, 10, 14};
    for (int i = 0; i < 4; ++i) {
        Image part = readExr(dir / ("split/merged.parts/part-000" + std::to_string(i) + ".exr"));
        EXPECT_EQ(part.meta.spp, spp[i]) << i;
        EXPECT_EQ(part.meta.sampleOffset, offset[i]) << i;
    }
    // The merge equals one render of all 18 samples up to float rounding ...
    ASSERT_EQ(test::runPenumbra("render " + q(dir / "scene.json") + " --quiet --spp 18 -o " + q(dir / "full.exr"), &err), 0)
        << err;
    Image merged = readExr(dir / "split/merged.exr"), full = readExr(dir / "full.exr");
    EXPECT_EQ(merged.meta.spp, 18);
    ASSERT_EQ(merged.rgb.size(), full.rgb.size());
    for (size_t k = 0; k < full.rgb.size(); ++k)
        ASSERT_NEAR(merged.rgb[k], full.rgb[k], 2e-5f * (1.0f + std::abs(full.rgb[k]))) << "value " << k;
    // ... and, statistically, an independent render (other seed) of the same image: the
    // per-pixel differences have mean zero (paired t-test over pixels, alpha = 1e-3).
    ASSERT_EQ(test::runPenumbra("render " + q(dir / "scene.json") + " --quiet --spp 18 --seed 7 -o " +
                                    q(dir / "independent.exr"),
                                &err),
              0);
    Image other = readExr(dir / "independent.exr");
    const size_t n = merged.rgb.size() / 3;
    double sum = 0, sum2 = 0;
    for (size_t p = 0; p < n; ++p) {
        double d = double(merged.rgb[3 * p]) - other.rgb[3 * p];
        sum += d;
        sum2 += d * d;
    }
    double mean = sum / n, var = (sum2 - n * mean * mean) / (n - 1);
    ASSERT_GT(var, 0.0) << "the two renders should differ pixel by pixel";
    double t = mean / std::sqrt(var / n);
    EXPECT_LT(std::abs(t), test::tCritical(1e-3, 1, int(n) - 1)) << "mean difference " << mean;
}
