// Scene textures and mesh uvs -> GPU arrays (see texture_arrays.h).
#include "render/texture_arrays.h"

#include <cstring>

namespace penumbra {

static_assert(uint32_t(TextureWrap::Repeat) == gpu::TEXTURE_WRAP_REPEAT &&
              uint32_t(TextureWrap::Clamp) == gpu::TEXTURE_WRAP_CLAMP &&
              uint32_t(TextureWrap::Mirror) == gpu::TEXTURE_WRAP_MIRROR);

uint32_t gpuTextureSlot(TextureSlot slot) {
    switch (slot) {
        case TextureSlot::Kd: return gpu::TEXTURE_SLOT_KD;
        case TextureSlot::Ks: return gpu::TEXTURE_SLOT_KS;
        case TextureSlot::KsX: return gpu::TEXTURE_SLOT_KS_X;
        case TextureSlot::KsY: return gpu::TEXTURE_SLOT_KS_Y;
        case TextureSlot::Emission: return gpu::TEXTURE_SLOT_EMISSION;
        case TextureSlot::Alpha: return gpu::TEXTURE_SLOT_ALPHA;
        case TextureSlot::Normal: return gpu::TEXTURE_SLOT_NORMAL;
    }
    return gpu::TEXTURE_SLOT_KD;
}

// One value per primitive in the BVH's leaf order, as the per-triangle bindings want them:
// `triangle(shape, t)` for triangle t (its first index) of each mesh, T{} for every other shape's
// one primitive (the order buildSceneArrays emits primitives in, mapped by bvh.originalIndex).
template <class T, class PerTriangle>
static std::vector<T> leafOrder(const Scene& scene, const Bvh& bvh, PerTriangle triangle) {
    std::vector<T> input;
    input.reserve(bvh.originalIndex.size());
    for (const Shape& shape : scene.shapes) {
        if (shape.type != ShapeType::Mesh) {
            input.push_back({});
            continue;
        }
        for (size_t t = 0; t + 2 < shape.indices.size(); t += 3) input.push_back(triangle(shape, t));
    }
    input.resize(bvh.originalIndex.size());  // instances (PRIM_INSTANCE, after the shapes' primitives): T{}
    std::vector<T> out(bvh.originalIndex.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = input.at(bvh.originalIndex[i]);
    return out;
}

TextureArrays buildTextureArrays(const Scene& scene, const Bvh& bvh) {
    TextureArrays out;
    for (const Material& m : scene.materials) {
        out.textured |= !m.textures.empty();
        for (const MaterialTexture& mt : m.textures) {
            out.transformed |= !mt.uvTransform.isIdentity();
            out.alphaMask |= mt.slot == TextureSlot::Alpha;
            out.normalMap |= mt.slot == TextureSlot::Normal;
        }
    }
    // Emission textures count where an emitting shape uses the material (the GPU reads them
    // only for primitives with a light).
    for (const Shape& shape : scene.shapes)
        if (shape.isEmitter())
            for (const MaterialTexture& mt : scene.materials.at(shape.material).textures)
                out.emission |= mt.slot == TextureSlot::Emission;
    if (!out.textured) return out;

    // Texels: every texture after the previous one, two RGBA half texels per uvec4.
    std::vector<uint32_t> firstTexel;
    std::vector<uint16_t> halves;
    for (const Texture& t : scene.textures) {
        firstTexel.push_back(uint32_t(halves.size() / 4));
        halves.insert(halves.end(), t.texels.begin(), t.texels.end());
    }
    halves.resize((halves.size() + 7) / 8 * 8, 0);  // whole uvec4s
    out.texels.resize(halves.size() / 8);
    std::memcpy(out.texels.data(), halves.data(), halves.size() * sizeof(uint16_t));

    // One header texel per material, then the references.
    out.materialTextures.resize(scene.materials.size(), glm::uvec4(0));
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        out.materialTextures[i] = glm::uvec4(uint32_t(out.materialTextures.size()), uint32_t(m.textures.size()), 0, 0);
        for (const MaterialTexture& mt : m.textures) {
            const Texture& t = scene.textures[mt.texture];
            gpu::TextureRef ref{};
            ref.scale = mt.scale;
            ref.slotChannel = gpuTextureSlot(mt.slot) | mt.channel << 8;
            ref.firstTexel = firstTexel[mt.texture];
            ref.width = t.width;
            ref.height = t.height;
            ref.wrap = uint32_t(mt.wrapU) | uint32_t(mt.wrapV) << 2;
            glm::uvec4 words[gpu::TEXTURE_REF_TEXELS];
            static_assert(sizeof words == sizeof ref);
            std::memcpy(words, &ref, sizeof ref);
            out.materialTextures.insert(out.materialTextures.end(), std::begin(words), std::end(words));
            // Only a scene with some transform carries them (SPEC_TEXTURES, TEXTURES_TRANSFORMED).
            if (out.transformed) {
                gpu::TextureTransform transform{glm::vec4(mt.uvTransform.u, 0.0f), glm::vec4(mt.uvTransform.v, 0.0f)};
                glm::uvec4 rows[gpu::TEXTURE_TRANSFORM_TEXELS];
                static_assert(sizeof rows == sizeof transform);
                std::memcpy(rows, &transform, sizeof transform);
                out.materialTextures.insert(out.materialTextures.end(), std::begin(rows), std::end(rows));
            }
        }
    }

    // Mesh uvs (zero where a mesh has none); tangents only for scenes with normal maps.
    out.uvs = leafOrder<gpu::TriangleUvs>(scene, bvh, [](const Shape& shape, size_t t) {
        gpu::TriangleUvs uv{};
        if (!shape.uvs.empty()) {
            glm::vec2 a = shape.uvs[shape.indices[t]], b = shape.uvs[shape.indices[t + 1]],
                      c = shape.uvs[shape.indices[t + 2]];
            uv.uv01 = glm::vec4(a, b);
            uv.uv2 = glm::vec4(c, 0.0f, 0.0f);
        }
        return uv;
    });
    if (out.normalMap)
        out.tangents = leafOrder<gpu::TriangleTangents>(scene, bvh, [](const Shape& shape, size_t t) {
            gpu::TriangleTangents tt{};
            if (!shape.tangents.empty())
                tt = {shape.tangents[shape.indices[t]], shape.tangents[shape.indices[t + 1]],
                      shape.tangents[shape.indices[t + 2]]};
            return tt;
        });
    return out;
}

}  // namespace penumbra
