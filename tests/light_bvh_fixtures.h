// Light-BVH test inputs shared by tests/test_light_bvh.cpp (host) and
// tests/test_light_bvh_gpu.cpp (GPU against host): lights of every kind with a position
// and shading points around them, from fixed seeds.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "render/light_bvh.h"

namespace penumbra::test {

// Point, spot, sphere and one-sided and two-sided triangle lights scattered over a box,
// powers over four decades.
inline std::vector<LightBounds> mixedLights(uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<LightBounds> lights;
    for (uint32_t i = 0; i < count; ++i) {
        glm::vec3 p(u(rng) * 10.0f - 5.0f, u(rng) * 2.0f + 0.5f, u(rng) * 10.0f - 5.0f);
        float power = std::pow(10.0f, 4.0f * u(rng));
        glm::vec3 dir = glm::normalize(glm::vec3(u(rng) - 0.5f, -1.0f, u(rng) - 0.5f));
        switch (i % 5) {
            case 0: lights.push_back(pointLightBounds(p, power, i)); break;
            case 1: lights.push_back(spotLightBounds(p, dir, 0.9f, 0.7f, power, i)); break;
            case 2: lights.push_back(sphereLightBounds(p, 0.1f + 0.3f * u(rng), power, i)); break;
            default: {
                glm::vec3 a = p, b = p + glm::vec3(0.3f, 0.0f, 0.1f), c = p + glm::vec3(0.0f, 0.2f * u(rng), 0.3f);
                glm::vec3 cr = glm::cross(b - a, c - a);
                lights.push_back(flatLightBounds(glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c)), cr,
                                                 0.5f * glm::length(cr), power, i % 5 == 4, 7, i));
            }
        }
    }
    return lights;
}

struct Shading {
    glm::vec3 p, n;
};

inline std::vector<Shading> shadingPoints(uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Shading> points;
    for (uint32_t i = 0; i < count; ++i) {
        glm::vec3 p(u(rng) * 14.0f - 7.0f, u(rng) * 3.0f, u(rng) * 14.0f - 7.0f);
        glm::vec3 n = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng), u(rng) - 0.5f));
        points.push_back({p, i % 7 == 0 ? glm::vec3(0.0f) : n});
    }
    return points;
}

}  // namespace penumbra::test
