// Kernel binaries on disk (see kernel_binaries.h).
#include "gpu/kernel_binaries.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <system_error>

namespace penumbra::gpu {

uint64_t fnv1a64(const void* bytes, size_t size, uint64_t seed) {
    const auto* p = static_cast<const unsigned char*>(bytes);
    uint64_t h = seed;
    for (size_t i = 0; i < size; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

std::optional<std::filesystem::path> KernelBinaries::folderFromEnvironment() {
    if (const char* dir = std::getenv("PENUMBRA_KERNEL_CACHE"); dir != nullptr && dir[0] != '\0') {
        if (std::string(dir) == "off") return std::nullopt;
        return std::filesystem::path(dir);
    }
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && xdg[0] == '/')
        return std::filesystem::path(xdg) / "penumbra" / "kernels";
    if (const char* home = std::getenv("HOME"); home != nullptr && home[0] == '/')
        return std::filesystem::path(home) / ".cache" / "penumbra" / "kernels";
    return std::nullopt;
}

std::filesystem::path KernelBinaries::fileFor(const std::string& key) const {
    // Two different seeds: 128 bits of name, so that two keys practically never share a file
    // (and if they did, the driver's checksum and UUID checks and the key stored in the file
    // would still refuse the wrong binary).
    const uint64_t a = fnv1a64(key.data(), key.size());
    const uint64_t b = fnv1a64(key.data(), key.size(), 0x84222325cbf29ce4ull);
    char name[64];
    std::snprintf(name, sizeof name, "%016llx%016llx.bin", static_cast<unsigned long long>(a),
                  static_cast<unsigned long long>(b));
    return m_folder.value_or(std::filesystem::path()) / name;
}

// A stored file is the key's length (8 bytes, little-endian), the key, then the binary: a
// file whose key differs from the one asked for is another kernel's, and is not used.
std::optional<std::vector<uint8_t>> KernelBinaries::load(const std::string& key) const {
    if (!m_folder) return std::nullopt;
    // Only a regular file of a binary's size is read: a FIFO or device put in its place
    // would block the open or the read, a huge file would be held whole.
    std::error_code error;
    const std::filesystem::path file = fileFor(key);
    const auto status = std::filesystem::status(file, error);
    if (error || !std::filesystem::is_regular_file(status)) return std::nullopt;
    const auto size = std::filesystem::file_size(file, error);
    if (error || size > kMaxFileBytes) return std::nullopt;
    std::ifstream in(file, std::ios::binary);
    if (!in) return std::nullopt;
    std::vector<uint8_t> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (data.size() < 8) return std::nullopt;
    uint64_t keySize = 0;
    for (int i = 0; i < 8; ++i) keySize |= uint64_t(data[size_t(i)]) << (8 * i);
    if (keySize != key.size() || data.size() < 8 + keySize) return std::nullopt;
    if (!std::equal(key.begin(), key.end(), data.begin() + 8)) return std::nullopt;
    return std::vector<uint8_t>(data.begin() + 8 + std::ptrdiff_t(keySize), data.end());
}

void KernelBinaries::store(const std::string& key, const std::vector<uint8_t>& bytes) const {
    if (!m_folder || bytes.empty()) return;
    std::error_code error;
    std::filesystem::create_directories(*m_folder, error);
    if (error) return;
    const std::filesystem::path target = fileFor(key);
    std::filesystem::path tmp = target;
    tmp += ".tmp-" + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return;
        char size[8];
        for (int i = 0; i < 8; ++i) size[i] = char((uint64_t(key.size()) >> (8 * i)) & 0xff);
        out.write(size, 8);
        out.write(key.data(), std::streamsize(key.size()));
        out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        if (!out.flush()) {
            out.close();
            std::filesystem::remove(tmp, error);
            return;
        }
    }
    std::filesystem::rename(tmp, target, error);
    if (error) {
        std::filesystem::remove(tmp, error);
        return;
    }
    // The oldest binaries past the limit go (by modification time; a binary taken back is
    // not touched, so this is least recently compiled, which for a cache of this size is
    // close enough to least recently used).
    std::vector<std::pair<std::filesystem::file_time_type, std::filesystem::path>> files;
    std::filesystem::directory_iterator it(*m_folder, error), end;
    for (; !error && it != end; it.increment(error)) {
        // The file just written always stays: mtimes tick coarsely, so it may tie with older ones.
        if (it->path().extension() != ".bin" || it->path() == target) continue;
        std::error_code timeError;
        auto time = it->last_write_time(timeError);
        if (!timeError) files.emplace_back(time, it->path());
    }
    if (files.size() < kMaxFiles) return;
    std::sort(files.begin(), files.end());
    for (size_t i = 0; i + kMaxFiles - 1 < files.size(); ++i) std::filesystem::remove(files[i].second, error);
}

}  // namespace penumbra::gpu
