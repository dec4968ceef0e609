// The `file` of an `environment` light (SCENE_FORMAT.md): an equirectangular OpenEXR or
// Radiance HDR image, read through image/image_file and checked as scene input (docs/guide/integrators.md,
// "Environment maps": formats, texel values and size limits).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>

#include <glm/glm.hpp>

#include "scene/json_reader.h"
#include "scene/scene.h"

namespace penumbra {

// Largest map: 2^25 texels (8192 x 4096, the size of the largest common sky maps); the GPU
// holds 32 bytes per texel (radiance RGBA32F and an alias-table entry): 1 GiB at this size.
inline constexpr uint64_t kMaxEnvironmentTexels = uint64_t(1) << 25;

// Reads the map `fileField` names, relative to `baseDir`, multiplied by `radiance` (the
// light's radiance is radiance x texel). Fails on `fileField` (the scene file and JSON path,
// then the image file and why) when the file is missing, outside the scene's folder
// (unless any path is allowed), not OpenEXR or Radiance HDR, corrupt, too large, holds a
// negative, NaN or infinite texel, or when radiance x texel exceeds kMaxRadiometric.
std::shared_ptr<const EnvironmentImage> readEnvironmentFile(const JsonReader& fileField,
                                                            const std::filesystem::path& baseDir, glm::vec3 radiance);

}  // namespace penumbra
