// AOV sums -> layers (see aov_layers.h; formulas in SCENE_FORMAT.md "AOVs (v3)").
#include "render/aov_layers.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "image/aov_channels.h"
#include "scene/aov_names.h"
#include "shared/aov.h"

namespace penumbra {

namespace {

constexpr uint32_t kNoId = 4294967295u;

// The kernel's bit of each name, in kAovNames' order.
constexpr uint32_t kBits[] = {gpu::AOV_ALBEDO,   gpu::AOV_NORMAL,       gpu::AOV_POSITION,    gpu::AOV_DEPTH,
                              gpu::AOV_SHAPE_ID, gpu::AOV_PRIMITIVE_ID, gpu::AOV_MATERIAL_ID, gpu::AOV_VARIANCE};
static_assert(std::size(kBits) == kAovNames.size());

// Input primitive index -> (shape in scene.shapes, triangle within it), as
// buildSceneArrays flattens the shapes (render/scene_arrays.cpp, flattenShapes): a sphere or
// quad is one primitive, a mesh one per index triple.
struct PrimitiveOwner {
    uint32_t shape, triangle;
};
std::vector<PrimitiveOwner> primitiveOwners(const Scene& scene) {
    std::vector<PrimitiveOwner> owners;
    for (uint32_t s = 0; s < scene.shapes.size(); ++s) {
        const Shape& shape = scene.shapes[s];
        const size_t count = shape.type == ShapeType::Mesh ? shape.indices.size() / 3 : 1;
        for (size_t t = 0; t < count; ++t) owners.push_back({s, uint32_t(t)});
    }
    return owners;
}

// Scene::materials index -> the contract's: sorted `materials` keys first (Scene::materials
// 1..n, as the loader adds them), then glTF materials; the built-in default (index 0, for
// shapes that name none) numbers last.
uint32_t materialId(const Scene& scene, uint32_t index) {
    return index == 0 ? uint32_t(scene.materials.size() - 1) : index - 1;
}

AovLayer floatLayer(const std::string& name, std::vector<std::string> channels, size_t pixels) {
    AovLayer layer;
    layer.name = name;
    layer.channels = std::move(channels);
    layer.floats.assign(pixels * layer.channels.size(), 0.0f);
    return layer;
}

AovLayer idLayer(const std::string& name, size_t pixels) {
    AovLayer layer;
    layer.name = name;
    layer.channels = {name};
    layer.ids.assign(pixels, kNoId);
    return layer;
}

}  // namespace

uint32_t aovBits(const std::vector<std::string>& names) {
    uint32_t bits = 0;
    for (const std::string& name : names)
        for (size_t i = 0; i < kAovNames.size(); ++i)
            if (kAovNames[i] == name) bits |= kBits[i];
    return bits;
}

std::vector<AovLayer> aovLayers(const std::vector<std::string>& names, const std::vector<glm::vec4>& sums,
                                const Image& image, const Scene& scene, const Bvh& bvh) {
    const size_t pixels = size_t(image.width) * image.height;
    const std::vector<PrimitiveOwner> owners = primitiveOwners(scene);
    std::vector<AovLayer> layers;
    for (const std::string& name : names) {
        AovLayer layer = aovHoldsIds(name) ? idLayer(name, pixels) : floatLayer(name, aovChannels(name), pixels);
        for (size_t i = 0; i < pixels; ++i) {
            const glm::vec4* a = &sums[i * gpu::AOV_VEC4S];
            const double count = a[0].w, hits = a[2].w;
            float* out = layer.floats.empty() ? nullptr : &layer.floats[i * layer.channels.size()];
            if (name == "albedo" && count > 0) {
                for (int c = 0; c < 3; ++c) out[c] = float(a[0][c] / count);
            } else if (name == "normal" && count > 0) {
                for (int c = 0; c < 3; ++c) out[c] = float(a[1][c] / count);
            } else if (name == "position" && count > 0) {
                for (int c = 0; c < 3; ++c) out[c] = float(a[2][c] / count);
            } else if (name == "depth") {
                out[0] = hits > 0 ? float(a[1].w / hits) : std::numeric_limits<float>::infinity();
            } else if (name == "variance") {
                // s^2 / N with s^2 = (sum x^2 - N mean^2) / (N - 1), the unbiased sample
                // variance: an unbiased estimate of the mean's variance. Rounding can take
                // the difference below 0, which no variance is; one sample gives no estimate (0).
                for (int c = 0; c < 3; ++c) {
                    const double mean = image.rgb[3 * i + c];
                    const double s2 = count > 1 ? (double(a[3][c]) - count * mean * mean) / (count - 1) : 0.0;
                    out[c] = float(std::max(s2, 0.0) / std::max(count, 1.0));
                }
            } else if (!layer.ids.empty()) {
                uint32_t leaf;
                const float word = a[3].w;
                std::memcpy(&leaf, &word, sizeof leaf);
                if (leaf == kNoId || leaf >= bvh.primitives.size()) continue;
                const PrimitiveOwner owner = owners.at(bvh.originalIndex[leaf]);
                layer.ids[i] = name == "shape_id"       ? owner.shape
                               : name == "primitive_id" ? owner.triangle
                                                        : materialId(scene, bvh.primitives[leaf].material);
            }
        }
        layers.push_back(std::move(layer));
    }
    return layers;
}

}  // namespace penumbra
