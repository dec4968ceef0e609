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

// Glossy Phong plates (exponents 20 and 300) and a diffuse floor lit by a sphere light, a
// quad light and a point light, seen at an angle. Every strategy has finite variance here
// (unlike the Veach scene, where BRDF sampling of tiny lights from diffuse surfaces has
// heavy tails that no t-test at affordable spp can handle).
// `closeUp` frames the sharp plate's highlight, where a wrong glossy density would show.
inline nlohmann::json glossyPlatesScene(int spp, uint32_t seed, const nlohmann::json& integrator,
                                        bool closeUp = false) {
    using nlohmann::json;
    json camera = closeUp ? json{{"eye", {0.9, 2.2, 4.5}}, {"target", {0.9, 0.75, -0.65}}, {"fov_y", 10}}
                          : json{{"eye", {0, 2.2, 4.5}}, {"target", {0, 0.3, 0}}, {"fov_y", 40}};
    return {
        {"camera", camera},
        {"film", {{"width", 48}, {"height", 32}}},
        {"sampler", {{"spp", spp}, {"seed", seed}}},
        {"integrator", integrator},
        {"materials",
         {{"floor", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}}},
          {"rough", {{"type", "phong"}, {"kd", {0.3, 0.2, 0.1}}, {"ks", {0.5, 0.5, 0.5}}, {"exponent", 20}}},
          {"sharp", {{"type", "phong"}, {"kd", {0.05, 0.1, 0.2}}, {"ks", {0.7, 0.7, 0.7}}, {"exponent", 300}}}}},
        {"shapes",
         {{{"type", "quad"},
           {"origin", {-4, 0, -4}},
           {"edge_u", {0, 0, 8}},
           {"edge_v", {8, 0, 0}},
           {"material", "floor"}},
          {{"type", "quad"},
           {"origin", {-1.6, 0.3, -0.2}},
           {"edge_u", {1.4, 0, 0}},
           {"edge_v", {0, 0.9, -0.9}},
           {"material", "rough"}},
          {{"type", "quad"},
           {"origin", {0.2, 0.3, -0.2}},
           {"edge_u", {1.4, 0, 0}},
           {"edge_v", {0, 0.9, -0.9}},
           {"material", "sharp"}},
          {{"type", "sphere"}, {"center", {-0.8, 2.6, 0.6}}, {"radius", 0.35}, {"power", {60, 50, 40}}},
          {{"type", "quad"},
           {"origin", {0.5, 2.6, 0.3}},
           {"edge_u", {0.8, 0, 0}},
           {"edge_v", {0, 0, 0.5}},
           {"emission", {6, 7, 9}}}}},
        {"lights", {{{"type", "point"}, {"position", {2, 3, 2}}, {"power", {30, 30, 30}}}}},
    };
}

// A tiny lit scene: a floor, a sphere, a sphere light and a point light, so that both
// integrators (and every light-selection mode) produce a non-trivial image.
inline nlohmann::json smallLitScene() {
    return floorAndSphereScene(
        {.width = 16, .height = 12, .spp = 4, .floorMaterial = true, .sphereLight = true, .pointLight = true});
}

}  // namespace penumbra::test
