// The SPIR-V of every compute shader under shaders/, embedded at build time by
// cmake/EmbedShaders.cmake. Names are paths without extension: "integrators/ao".
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace penumbra {
std::span<const uint32_t> shaderCode(std::string_view name);
// Every embedded shader's name.
std::vector<std::string_view> shaderNames();
}
