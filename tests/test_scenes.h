// Scenes that several test files render: one definition each, with the parts a test needs
// switched on by options.
#pragma once

#include <cstdint>

#include <nlohmann/json.hpp>

namespace penumbra::test {

// The floor-and-sphere scene: a 4 x 4 floor quad at y = 0 and a sphere of radius 0.5 resting
// on it, seen from (0, 1, 4) with a 40 degree field of view.
struct FloorAndSphere {
    uint32_t width = 16, height = 12;
    uint32_t spp = 0;  // 0: no sampler section (the defaults)
    const char* integrator = "direct";
    bool floorMaterial = false;  // the floor diffuse with albedo 0.5 (else the default 0.8)
    bool sphereLight = false;    // a sphere light of radius 0.3 at (1, 2, 1), radiance 5
    bool pointLight = false;     // a 20 W point light at (-1, 2, 1)
};

// A film of 37 x 35 pixels (five rows of 8 x 8 tiles, which most slice counts do not
// divide) over a 6 x 6 floor lit by a 1 x 1 quad light 2 above it, direct lighting with
// MIS, so that every pixel sample draws random numbers: for tests that render the same
// samples in differently shaped dispatches and compare the images bit for bit. They add
// shapes that vary the pixels.
inline nlohmann::json litFloorOnOddFilmScene(uint32_t spp, uint32_t seed) {
    using nlohmann::json;
    return {
        {"camera", {{"eye", {0, 2, 3}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_y", 50}}},
        {"film", {{"width", 37}, {"height", 35}}},
        {"sampler", {{"spp", spp}, {"seed", seed}}},
        {"integrator", {{"type", "direct"}, {"strategy", "mis"}}},
        {"shapes",
         {{{"type", "quad"}, {"origin", {-3, 0, -3}}, {"edge_u", {0, 0, 6}}, {"edge_v", {6, 0, 0}}},
          {{"type", "quad"},
           {"origin", {-0.5, 2, -0.5}},
           {"edge_u", {1, 0, 0}},
           {"edge_v", {0, 0, 1}},
           {"emission", 5}}}},
    };
}

inline nlohmann::json floorAndSphereScene(const FloorAndSphere& o) {
    using nlohmann::json;
    json floor = {{"type", "quad"}, {"origin", {-2, 0, -2}}, {"edge_u", {0, 0, 4}}, {"edge_v", {4, 0, 0}}};
    if (o.floorMaterial) floor["material"] = "floor";
    json shapes = {floor, {{"type", "sphere"}, {"center", {0, 0.5, 0}}, {"radius", 0.5}}};
    if (o.sphereLight)
        shapes.push_back({{"type", "sphere"}, {"center", {1, 2, 1}}, {"radius", 0.3}, {"emission", {5, 5, 5}}});
    json scene = {
        {"camera", {{"eye", {0, 1, 4}}, {"target", {0, 0.5, 0}}, {"fov_y", 40}}},
        {"film", {{"width", o.width}, {"height", o.height}}},
        {"integrator", {{"type", o.integrator}}},
        {"shapes", shapes},
    };
    if (o.spp > 0) scene["sampler"] = {{"spp", o.spp}};
    if (o.floorMaterial) scene["materials"] = {{"floor", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}}}};
    if (o.pointLight) scene["lights"] = {{{"type", "point"}, {"position", {-1, 2, 1}}, {"power", {20, 20, 20}}}};
    return scene;
}

}  // namespace penumbra::test
