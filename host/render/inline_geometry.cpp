// Inline geometry: the rule and the specialization words (see inline_geometry.h).
#include "render/inline_geometry.h"

#include <bit>
#include <stdexcept>
#include <string>

namespace penumbra {

bool inlineGeometryPays(const SceneArrays& arrays) {
    const size_t n = arrays.bvh.primitives.size();
    return n > 0 && n <= size_t(INLINE_MAX_PRIMITIVES);
}

uint32_t inlineKernelCapacity(uint32_t count) {
    static_assert(INLINE_MAX_PRIMITIVES % INLINE_CAPACITY_STEP == 0);
    if (count == 0 || count > uint32_t(INLINE_MAX_PRIMITIVES))
        throw std::logic_error("inlineKernelCapacity: no inline kernel for " + std::to_string(count) + " primitives");
    return (count + INLINE_CAPACITY_STEP - 1) / INLINE_CAPACITY_STEP * INLINE_CAPACITY_STEP;
}

std::vector<uint32_t> inlineGeometryWords(const std::vector<gpu::Primitive>& primitives) {
    if (primitives.size() > size_t(INLINE_MAX_PRIMITIVES))
        throw std::logic_error("inlineGeometryWords: more primitives than the kernel declares");
    std::vector<uint32_t> words;
    words.reserve(primitives.size() * INLINE_PRIMITIVE_WORDS);
    for (const gpu::Primitive& p : primitives) {
        words.push_back(p.typeAndNormals & gpu::PRIM_TYPE_MASK);
        for (const glm::vec3& v : {p.p0, p.p1, p.p2})
            for (int k = 0; k < 3; ++k) words.push_back(std::bit_cast<uint32_t>(v[k]));
    }
    return words;
}

}  // namespace penumbra
