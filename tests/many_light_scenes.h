// Closed-form many-light scenes shared by the light-selection and RIS render tests: point
// lights of powers over four decades above the plane y = 0 (their irradiance there is an
// exact sum), and a small emitting mesh whose outline gives the polygon formula
// (render_helpers.h, polygonIrradiance), over a diffuse plane.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include <nlohmann/json.hpp>

#include "render_helpers.h"

namespace penumbra::test {

// A diffuse plane y = 0 of grey albedo `albedo` (100 x 100, so that it fills the view), a
// black material "black" for emitters and no lights yet, seen top-down on a 32 x 32 film:
// the camera sees [cx - half, cx + half] x [-half, half] of it (topDownCamera).
inline nlohmann::json diffusePlaneScene(int spp, uint32_t seed, double cx, double half, double albedo) {
    using nlohmann::json;
    return {
        {"camera", topDownCamera(cx, 0.0, half)},
        {"film", {{"width", 32}, {"height", 32}}},
        {"sampler", {{"spp", spp}, {"seed", seed}}},
        {"materials",
         {{"plane", {{"type", "diffuse"}, {"albedo", {albedo, albedo, albedo}}}},
          {"black", {{"type", "diffuse"}, {"albedo", {0, 0, 0}}}}}},
        {"shapes", json::array({{{"type", "quad"},
                                 {"origin", {-50, 0, -50}},
                                 {"edge_u", {0, 0, 100}},
                                 {"edge_v", {100, 0, 0}},
                                 {"material", "plane"}}})},
        {"lights", json::array()},
    };
}

struct PointLight {
    glm::dvec3 position;
    double intensity;
};

// `count` point lights over [-4, 4]^2 at heights 0.5 to 2, intensities 0.01 to 100 W/sr.
inline std::vector<PointLight> randomPointLights(int count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<PointLight> lights;
    for (int i = 0; i < count; ++i)
        lights.push_back(
            {{8.0 * u(rng) - 4.0, 0.5 + 1.5 * u(rng), 8.0 * u(rng) - 4.0}, 0.01 * std::pow(10.0, 4.0 * u(rng))});
    return lights;
}

// Appends the lights to doc["lights"] as "point" lights of grey intensity.
inline void addPointLights(nlohmann::json& doc, const std::vector<PointLight>& lights) {
    for (const PointLight& l : lights)
        doc["lights"].push_back({{"type", "point"},
                                 {"position", {l.position.x, l.position.y, l.position.z}},
                                 {"intensity", {l.intensity, l.intensity, l.intensity}}});
}

// Irradiance at x on the plane y = 0 (normal +y) from the point lights: sum I cos(theta) / d^2.
inline double pointLightsIrradiance(const std::vector<PointLight>& lights, glm::dvec3 x) {
    double sum = 0.0;
    for (const PointLight& l : lights) {
        glm::dvec3 d = l.position - x;
        double d2 = glm::dot(d, d);
        sum += l.intensity * (d.y / std::sqrt(d2)) / d2;
    }
    return sum;
}

// Appends a downward-facing emitting mesh (radiance Le, material "black") at height h over
// [-2, 2] x [3.5, 7.5]: a 2 x 2 grid of squares, two triangles each, counter-clockwise seen
// from below (their front faces the plane), so that a light BVH has 8 triangle items. Returns
// its outline for polygonIrradiance.
inline std::vector<glm::dvec3> addEmittingSquareMesh(nlohmann::json& doc, double Le, double h) {
    nlohmann::json positions = nlohmann::json::array(), indices = nlohmann::json::array();
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 2; ++i) positions.insert(positions.end(), {-2.0 + 2.0 * i, h, 3.5 + 2.0 * j});
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            int a = j * 3 + i, b = a + 1, c = a + 3, d = a + 4;
            indices.insert(indices.end(), {a, b, c, b, d, c});
        }
    doc["shapes"].push_back({{"type", "mesh"},
                             {"positions", positions},
                             {"indices", indices},
                             {"emission", {Le, Le, Le}},
                             {"material", "black"}});
    return {{-2, h, 3.5}, {2, h, 3.5}, {2, h, 7.5}, {-2, h, 7.5}};
}

}  // namespace penumbra::test
