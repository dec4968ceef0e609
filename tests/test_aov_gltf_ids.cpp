// The id layers of a glTF model's primitives against SCENE_FORMAT.md's numbering ("AOVs
// (v3)", Numbering): a `gltf` shape at index k with P triangle primitives takes shape ids
// k .. k + P - 1 in the file's node and primitive order, the next shape k + P;
// primitive_id counts a primitive's triangles from 0; material_id numbers the sorted
// `materials` keys, then the file's materials, then the built-in default.
//
// The scene: the camera at (0, 0, 5) looks down -z at a wall (shape 0, z = -1, material
// "wall"), a glTF file (shape 1) of two nodes, each a 1.8 x 2 square of two triangles at
// z = 0 (left: shape 1, glTF material 1; right: shape 2, glTF material 0, so that file
// order and material order differ), and a sphere above them with no material (shape 3,
// the default material). Each pixel's expected ids come from its centre ray, intersected
// here in double precision; centres within 1e-3 of an edge are skipped.
#include <cmath>
#include <fstream>
#include <optional>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "gltf_builder.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;

namespace {

constexpr int kWidth = 24, kHeight = 12;
constexpr uint32_t kNoId = 4294967295u;
constexpr double kEdge = 1e-3;
const glm::dvec3 kEye(0, 0, 5), kSphere(0, 1.5, 0);
constexpr double kRadius = 0.3;

// The squares' corners, counter-clockwise from the bottom left; triangles (0, 1, 2) and (0, 2, 3).
const double kLeft[2] = {-2.0, -0.2}, kRight[2] = {0.2, 2.0};

std::vector<float> squareCorners(const double x[2]) {
    return {float(x[0]), -1, 0, float(x[1]), -1, 0, float(x[1]), 1, 0, float(x[0]), 1, 0};
}

std::string model() {
    test::GltfBuilder b;
    for (const double* x : {kLeft, kRight}) {
        json primitive = {{"attributes", {{"POSITION", b.positions(squareCorners(x))}}},
                          {"indices", b.indices({0, 1, 2, 0, 2, 3})},
                          {"material", x == kLeft ? 1 : 0}};
        b.addMeshNode(primitive);
    }
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.2, 0.2, 1}}}}},
                          {{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.8, 0.2, 1}}}}}};
    return b.gltf();
}

struct Ids {
    uint32_t shape, primitive, material;
};

// The centre ray of pixel (x, y) (the renderer's camera: integrators/kernel_common.glsl,
// cameraRay), or nullopt when it passes within kEdge of an edge or silhouette.
std::optional<Ids> expectedIds(int x, int y) {
    const double tanHalf = std::tan(20.0 * M_PI / 180.0), aspect = double(kWidth) / kHeight;
    const glm::dvec3 d = glm::normalize(
        glm::dvec3((2 * (x + 0.5) / kWidth - 1) * aspect * tanHalf, (1 - 2 * (y + 0.5) / kHeight) * tanHalf, -1));
    const glm::dvec3 oc = kEye - kSphere;
    const double b = glm::dot(oc, d), disc = b * b - (glm::dot(oc, oc) - kRadius * kRadius);
    if (std::abs(disc) < kEdge) return std::nullopt;
    if (disc > 0) return Ids{3, 0, 3};                // the sphere: after 1 named + 2 glTF materials, the default
    const glm::dvec3 p = kEye + d * (kEye.z / -d.z);  // the z = 0 plane
    if (std::abs(std::abs(p.y) - 1) < kEdge) return std::nullopt;
    for (int side = 0; side < 2; ++side) {
        const double* sx = side == 0 ? kLeft : kRight;
        if (std::abs(p.x - sx[0]) < kEdge || std::abs(p.x - sx[1]) < kEdge) return std::nullopt;
        if (p.x < sx[0] || p.x > sx[1] || std::abs(p.y) > 1) continue;
        // The diagonal from corner 0 (x0, -1) to corner 2 (x1, 1): triangle 0 lies below it.
        const double u = (p.x - sx[0]) / (sx[1] - sx[0]), v = (p.y + 1) / 2;
        if (std::abs(u - v) < kEdge) return std::nullopt;
        return Ids{uint32_t(1 + side), u > v ? 0u : 1u, side == 0 ? 2u : 1u};
    }
    return Ids{0, 0, 0};  // the wall, which fills the view behind
}

}  // namespace

TEST(AovGltfIds, PrimitivesNumberOnFromTheirShapeInFileOrder) {
    std::ofstream(test::outputPath("aov-gltf-ids.gltf")) << model();
    const json scene = {
        {"camera", {{"eye", {0, 0, 5}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fov_y", 40}}},
        {"film", {{"width", kWidth}, {"height", kHeight}, {"aovs", {"shape_id", "primitive_id", "material_id"}}}},
        {"sampler", {{"spp", 1}}},
        {"materials", {{"wall", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}}}}},
        {"shapes",
         {{{"type", "quad"},
           {"origin", {-6, -6, -1}},
           {"edge_u", {12, 0, 0}},
           {"edge_v", {0, 12, 0}},
           {"material", "wall"}},
          {{"type", "gltf"}, {"file", "aov-gltf-ids.gltf"}},
          {{"type", "sphere"}, {"center", {kSphere.x, kSphere.y, kSphere.z}}, {"radius", kRadius}}}},
        {"lights", {{{"type", "point"}, {"position", {0, 0, 4}}, {"power", 10}}}},
    };
    const Image image = test::renderJson(scene, "aov-gltf-ids");
    ASSERT_EQ(image.aovs.size(), 3u);
    int checked = 0, seen[4] = {0, 0, 0, 0}, triangles[2] = {0, 0};
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const std::optional<Ids> e = expectedIds(x, y);
            if (!e) continue;
            ++checked;
            ++seen[e->shape];
            if (e->shape == 1 || e->shape == 2) ++triangles[e->primitive];
            const size_t i = size_t(y) * kWidth + x;
            EXPECT_EQ(image.aovs[0].ids[i], e->shape) << "shape_id at " << x << "," << y;
            EXPECT_EQ(image.aovs[1].ids[i], e->primitive) << "primitive_id at " << x << "," << y;
            EXPECT_EQ(image.aovs[2].ids[i], e->material) << "material_id at " << x << "," << y;
            EXPECT_NE(image.aovs[0].ids[i], kNoId);
        }
    // Every shape and both triangles of the squares were checked somewhere.
    EXPECT_GT(checked, kWidth * kHeight * 3 / 4);
    for (int s = 0; s < 4; ++s) EXPECT_GT(seen[s], 0) << "shape " << s;
    EXPECT_GT(triangles[0], 0);
    EXPECT_GT(triangles[1], 0);
}
