// Packs each material kind into the two-texel GPU Material (see material_arrays.h and the
// layout notes beside struct Material in shaders/shared/types.h).
#include "render/material_arrays.h"

namespace penumbra {

gpu::Material packMaterial(const Material& m) {
    gpu::Material g{};
    switch (m.type) {
        case MaterialType::Diffuse:
            g.type = gpu::MATERIAL_DIFFUSE;
            g.kd = m.kd;
            g.exponent = m.exponent;
            break;
        case MaterialType::Phong:
            g.type = gpu::MATERIAL_PHONG;
            g.kd = m.kd;
            g.ks = m.ks;
            g.exponent = m.exponent;
            break;
        case MaterialType::Pbr:
            g.type = gpu::MATERIAL_PBR;
            g.kd = m.pbr.baseColor;
            g.ks = glm::vec3(m.pbr.metallic, m.pbr.roughness, 0.0f);
            break;
    }
    return g;
}

std::vector<gpu::Material> packMaterials(const std::vector<Material>& materials) {
    std::vector<gpu::Material> out;
    out.reserve(materials.size());
    for (const Material& m : materials) out.push_back(packMaterial(m));
    if (out.empty()) out.push_back({glm::vec3(0.8f), gpu::MATERIAL_DIFFUSE, glm::vec3(0.0f), 0.0f});
    return out;
}

}  // namespace penumbra
