// The kernels' driver binaries kept on disk between processes, where the driver can hand
// them out (VK_EXT_shader_object's vkGetShaderBinaryDataEXT) and taking one back saves
// work: lavapipe (gpu/shader_objects.h says when they are used).
//
// Why: lavapipe's VkPipelineCache keeps nothing, and Mesa's own disk cache keeps only the
// LLVM back end's output, so every process turned the kernel's SPIR-V into NIR, inlined
// and optimised it again: most of a small render's time and all of its peak memory
// (docs/PERFORMANCE.md, "Start-up"). A shader object's binary is that optimised NIR; from
// it the driver skips all of that.
//
// Where: $PENUMBRA_KERNEL_CACHE if set (the word "off" turns the cache off), else
// $XDG_CACHE_HOME/penumbra/kernels, else $HOME/.cache/penumbra/kernels. A binary is found
// by a hash of everything it depends on (the key's text: device, driver, binary UUID and
// version, the specialized SPIR-V, the layout); the driver checks its own UUID and
// checksum again when taking it back, and a binary it refuses is compiled anew and
// replaced. The folder keeps the kMaxFiles most recently written binaries. The cache is a
// help, never a requirement: a folder that cannot be made, read or written only costs the
// compilation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::gpu {

class KernelBinaries {
public:
    // How many binaries the folder keeps (20-100 KB each for the render kernels, so at most
    // some 50 MB): enough for every kernel the test suite compiles, bounded for batch sweeps
    // of small scenes' geometry, which compile one kernel per distinct geometry.
    static constexpr size_t kMaxFiles = 512;
    // A file larger than this is not read (the render kernels' binaries are under 1 MB).
    static constexpr uint64_t kMaxFileBytes = 64ull << 20;

    // The folder from the environment as above; none where the cache is off or no folder
    // can be named.
    static std::optional<std::filesystem::path> folderFromEnvironment();

    explicit KernelBinaries(std::optional<std::filesystem::path> folder) : m_folder(std::move(folder)) {}

    bool enabled() const { return m_folder.has_value(); }
    // The bytes stored under `key` (its hash names the file), if any.
    std::optional<std::vector<uint8_t>> load(const std::string& key) const;
    // Stores `bytes` under `key` (a temporary file, then a rename, so that a reader never
    // sees half a binary), then drops the oldest binaries past kMaxFiles. Errors are ignored.
    void store(const std::string& key, const std::vector<uint8_t>& bytes) const;

    // The file `key` is stored in.
    std::filesystem::path fileFor(const std::string& key) const;

private:
    std::optional<std::filesystem::path> m_folder;
};

// A 64-bit FNV-1a hash of `bytes` (file names only: the driver verifies what it loads).
uint64_t fnv1a64(const void* bytes, size_t size, uint64_t seed = 0xcbf29ce484222325ull);

}  // namespace penumbra::gpu
