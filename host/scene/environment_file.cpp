// Environment map files as scene input (see environment_file.h): path rules as for textures,
// the contract's formats only, texels checked before anything is uploaded.
#include "scene/environment_file.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/errors.h"
#include "core/stop_request.h"
#include "image/image_file.h"
#include "scene/limits.h"
#include "scene/scene_input_file.h"

namespace penumbra {

namespace fs = std::filesystem;

std::shared_ptr<const EnvironmentImage> readEnvironmentFile(const JsonReader& fileField, const fs::path& baseDir,
                                                            glm::vec3 radiance) {
    fs::path file = sceneRelativeInputFile(fileField, baseDir);
    ImageFile image;
    try {
        // ColorDecode only matters for 8-bit formats, which are refused below.
        image = readImageFile(file, file.string(), ColorDecode::Linear, kMaxEnvironmentTexels);
    } catch (const InputError& e) {
        fileField.fail(e.what());  // "scene.json: lights[0].file: FILE: why"
    }
    // The contract names EXR and Radiance HDR: 8-bit images hold display colours, not radiance.
    if (image.format != ImageFileFormat::Exr && image.format != ImageFileFormat::Hdr)
        fileField.fail(file.string() + ": an environment map must be an OpenEXR or Radiance HDR image, not " +
                       (image.format == ImageFileFormat::Png ? "PNG" : "JPEG"));
    auto map = std::make_shared<EnvironmentImage>();
    map->width = image.width;
    map->height = image.height;
    map->texels.reserve(size_t(image.width) * image.height);  // each written once, in order
    for (uint32_t y = 0; y < image.height; ++y) {
        throwIfStopRequested();  // an 8192 x 4096 map: a stop waits one row, not the map
        for (uint32_t x = 0; x < image.width; ++x) {
            const float* t = image.texel(x, y);
            glm::vec3 texel(t[0], t[1], t[2]);
            auto where = [&] {
                std::ostringstream s;
                s << file.string() << ": texel (" << x << ", " << y << ") = (" << texel.x << ", " << texel.y << ", "
                  << texel.z << ")";
                return s.str();
            };
            // The loader already refuses NaN and infinity; radiance is never negative.
            if (!(texel.x >= 0.0f && texel.y >= 0.0f && texel.z >= 0.0f))
                fileField.fail(where() + " is negative: radiance cannot be");
            glm::vec3 value = radiance * texel;
            double largest =
                std::max({double(radiance.x) * texel.x, double(radiance.y) * texel.y, double(radiance.z) * texel.z});
            if (!(largest <= kMaxRadiometric))
                fileField.fail(where() + " times radiance exceeds 1e20 (the limit of radiance values)");
            map->texels.push_back(value);
        }
    }
    return map;
}

}  // namespace penumbra
