// The SPIR-V of every compute shader under shaders/, embedded at build time by
// cmake/EmbedShaders.cmake. Names are paths without extension: "integrators/ao".
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace penumbra {
std::span<const uint32_t> shaderCode(std::string_view name);
}
