// Host side of the light-sampling test kernel (shaders/tests/light_sampling.comp): uploads
// a scene's arrays to the buffers at their BINDING_* numbers and runs the kernel's three
// modes. One pipeline serves every scene (lavapipe compiles it once per process). Shared by tests/test_light_sampling.cpp and tests/test_light_selection.cpp.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "render/scene_arrays.h"
#include "tests/light_sampling_test.h"

namespace penumbra::test {

class LightKernel {
public:
    explicit LightKernel(const SceneArrays& arrays);

    // `count` samples of light `light` from x (normal n): one record per sample. Quads and
    // mesh triangles are sampled by `quadSampling` (QUAD_*) and `triangleSampling` (TRIANGLE_*).
    std::vector<gpu::LightTestRecord> sample(uint32_t light, glm::vec3 x, glm::vec3 n, uint32_t sphereSampling,
                                             uint32_t seed, uint32_t count, uint32_t quadSampling = gpu::QUAD_AREA,
                                             uint32_t triangleSampling = gpu::TRIANGLE_AREA);
    // The traced pdf (see LIGHT_TEST_MODE_PDF) of each direction; with `hitDistance`, also the
    // distance of the first hit the pdf was evaluated at (0 when nothing was hit).
    std::vector<double> pdf(uint32_t light, glm::vec3 x, glm::vec3 n, uint32_t sphereSampling,
                            const std::vector<glm::vec3>& directions, std::vector<float>* hitDistance = nullptr,
                            uint32_t quadSampling = gpu::QUAD_AREA, uint32_t triangleSampling = gpu::TRIANGLE_AREA);
    // `count` draws from a selection table: (item, pmf) per draw.
    std::vector<gpu::LightTestRecord> select(uint32_t table, uint32_t offset, uint32_t tableCount, uint32_t seed,
                                             uint32_t count);

    // The smallest solid angle and vertex elevation (sine) at which quads and triangles are
    // sampled in solid angle (below: on their area); the integrator's SPHERICAL_MIN_SOLID_ANGLE
    // and SPHERICAL_MIN_ELEVATION_SINE unless lowered to measure the spherical warps.
    void setSphericalBounds(float minSolidAngle, float minElevationSine) {
        m_minSolidAngle = minSolidAngle;
        m_minElevationSine = minElevationSine;
    }

private:
    std::vector<gpu::LightTestRecord> run(gpu::LightTestPush push, const gpu::Buffer& in);
    // The push constants of a sample or pdf query of one light from the shading point (x, n).
    gpu::LightTestPush shadingPointPush(uint32_t mode, uint32_t light, glm::vec3 x, glm::vec3 n, uint32_t count,
                                        uint32_t sphereSampling, uint32_t quadSampling,
                                        uint32_t triangleSampling) const;

    gpu::Context& m_ctx;
    float m_minSolidAngle = gpu::SPHERICAL_MIN_SOLID_ANGLE;
    float m_minElevationSine = gpu::SPHERICAL_MIN_ELEVATION_SINE;
    gpu::Buffer m_dummy, m_nodes, m_primitives, m_normals, m_lights, m_lightTable, m_meshTable, m_environmentTexels,
        m_environmentTable;
    uint32_t m_besideFirst, m_besideCount;  // the primitives beside the BVH's tree (Bvh::besideCount)
};

}  // namespace penumbra::test
