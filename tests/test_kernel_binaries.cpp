// gpu::KernelBinaries: the kernels' driver binaries on disk between processes. A binary is
// found only under the exact key it was stored with, a damaged or foreign file is never
// handed out, the folder stays bounded, and a folder that cannot be used costs nothing but
// the compilation.
#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu/kernel_binaries.h"
#include "gpu_fixture.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

// Sets an environment variable for the scope (nullptr: unset), restoring the old value.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : m_name(name) {
        if (const char* old = std::getenv(name)) m_old = old;
        value ? setenv(name, value, 1) : unsetenv(name);
    }
    ~ScopedEnv() { m_old ? setenv(m_name, m_old->c_str(), 1) : unsetenv(m_name); }

private:
    const char* m_name;
    std::optional<std::string> m_old;
};

size_t filesIn(const fs::path& folder) {
    size_t n = 0;
    for (const auto& entry : fs::directory_iterator(folder)) n += entry.is_regular_file();
    return n;
}

const std::vector<uint8_t> kBytes = {1, 2, 3, 250, 0, 7};

}  // namespace

TEST(KernelBinaries, GivesBackWhatWasStoredUnderTheSameKeyOnly) {
    const fs::path folder = test::freshOutputDir("kernel_binaries", "same_key");
    gpu::KernelBinaries binaries(folder);
    EXPECT_FALSE(binaries.load("device A; kernel 1").has_value());
    binaries.store("device A; kernel 1", kBytes);
    EXPECT_EQ(binaries.load("device A; kernel 1"), kBytes);
    EXPECT_FALSE(binaries.load("device A; kernel 2").has_value());
    EXPECT_FALSE(binaries.load("device A; kernel 1 ").has_value());
    EXPECT_EQ(filesIn(folder), 1u);  // no temporary file left behind
}

TEST(KernelBinaries, AFileHoldingAnotherKeyIsNotUsed) {
    // As if two keys' names collided: the key stored inside the file decides.
    const fs::path folder = test::freshOutputDir("kernel_binaries", "foreign");
    gpu::KernelBinaries binaries(folder);
    binaries.store("kernel 1", kBytes);
    fs::copy_file(binaries.fileFor("kernel 1"), binaries.fileFor("kernel 2"));
    EXPECT_FALSE(binaries.load("kernel 2").has_value());
    EXPECT_EQ(binaries.load("kernel 1"), kBytes);
}

TEST(KernelBinaries, ATruncatedOrEmptyFileIsNotUsed) {
    const fs::path folder = test::freshOutputDir("kernel_binaries", "truncated");
    gpu::KernelBinaries binaries(folder);
    const std::string key = "a kernel whose key is longer than eight bytes";
    binaries.store(key, kBytes);
    const fs::path file = binaries.fileFor(key);
    fs::resize_file(file, 8 + key.size() / 2);  // the key cut short
    EXPECT_FALSE(binaries.load(key).has_value());
    fs::resize_file(file, 3);  // not even the key's length
    EXPECT_FALSE(binaries.load(key).has_value());
    fs::resize_file(file, 0);
    EXPECT_FALSE(binaries.load(key).has_value());
}

TEST(KernelBinaries, KeepsOnlyTheNewestFiles) {
    const fs::path folder = test::freshOutputDir("kernel_binaries", "bounded");
    gpu::KernelBinaries binaries(folder);
    const size_t stored = gpu::KernelBinaries::kMaxFiles + 20;
    for (size_t i = 0; i < stored; ++i) binaries.store("kernel " + std::to_string(i), kBytes);
    EXPECT_EQ(filesIn(folder), gpu::KernelBinaries::kMaxFiles);
    EXPECT_EQ(binaries.load("kernel " + std::to_string(stored - 1)), kBytes);  // the newest stays
}

TEST(KernelBinaries, AFolderThatCannotBeUsedOnlyCostsTheCompilation) {
    // A plain file where the folder should be: storing fails quietly, nothing is found.
    const fs::path blocker = test::freshOutputDir("kernel_binaries", "blocked") / "not-a-folder";
    std::ofstream(blocker) << "x";
    gpu::KernelBinaries binaries(blocker / "kernels");
    EXPECT_NO_THROW(binaries.store("kernel", kBytes));
    EXPECT_FALSE(binaries.load("kernel").has_value());
}

TEST(KernelBinaries, TheFolderComesFromTheEnvironment) {
    {
        ScopedEnv cache("PENUMBRA_KERNEL_CACHE", "off");
        EXPECT_FALSE(gpu::KernelBinaries::folderFromEnvironment().has_value());
    }
    {
        ScopedEnv cache("PENUMBRA_KERNEL_CACHE", "/somewhere/kernels");
        EXPECT_EQ(gpu::KernelBinaries::folderFromEnvironment(), fs::path("/somewhere/kernels"));
    }
    ScopedEnv cache("PENUMBRA_KERNEL_CACHE", nullptr);
    {
        ScopedEnv xdg("XDG_CACHE_HOME", "/xdg");
        EXPECT_EQ(gpu::KernelBinaries::folderFromEnvironment(), fs::path("/xdg/penumbra/kernels"));
    }
    ScopedEnv xdg("XDG_CACHE_HOME", nullptr);
    ScopedEnv home("HOME", "/home/someone");
    EXPECT_EQ(gpu::KernelBinaries::folderFromEnvironment(), fs::path("/home/someone/.cache/penumbra/kernels"));
}

TEST(KernelBinaries, ASpecialOrHugeFileInItsPlaceIsNotRead) {
    // A FIFO named like a binary would block the open for ever; an oversized file would be
    // read whole. Neither is read (a mutation that opens the FIFO hangs here).
    const fs::path folder = test::freshOutputDir("kernel_binaries", "special");
    gpu::KernelBinaries binaries(folder);
    ASSERT_EQ(mkfifo(binaries.fileFor("fifo kernel").c_str(), 0600), 0);
    EXPECT_FALSE(binaries.load("fifo kernel").has_value());
    binaries.store("huge kernel", kBytes);
    fs::resize_file(binaries.fileFor("huge kernel"), gpu::KernelBinaries::kMaxFileBytes + 1);  // sparse
    EXPECT_FALSE(binaries.load("huge kernel").has_value());
}
