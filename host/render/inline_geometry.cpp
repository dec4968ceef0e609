// Inline geometry: the rule and the specialization words (see inline_geometry.h).
#include "render/inline_geometry.h"

#include <bit>
#include <stdexcept>

namespace penumbra {

bool inlineGeometryPays(const SceneArrays& arrays) {
    const size_t n = arrays.bvh.primitives.size();
    return n > 0 && n <= size_t(INLINE_MAX_PRIMITIVES);
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
