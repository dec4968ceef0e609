// The host side of the lights (render/light_arrays.h) and the scene feature bits: every kind
// of primitive, light and material has a bit of its own, and a kind added to types.h without
// raising its *_KIND_COUNT is refused instead of setting another group's bit.
#include <gtest/gtest.h>

#include <memory>
#include <numbers>
#include <set>
#include <stdexcept>

#include "render/kernel_options.h"
#include "render/light_arrays.h"
#include "render/scene_arrays.h"

using namespace penumbra;

TEST(LightArrays, FeatureBitsOfAllKindsAreDistinctAndFitInOneWord) {
    std::set<uint32_t> bits;
    for (uint32_t k = 0; k < PRIM_KIND_COUNT; ++k) bits.insert(FEATURE_PRIMITIVE + k);
    for (uint32_t k = 0; k < LIGHT_KIND_COUNT; ++k) bits.insert(FEATURE_LIGHT + k);
    for (uint32_t k = 0; k < MATERIAL_KIND_COUNT; ++k) bits.insert(FEATURE_MATERIAL + k);
    EXPECT_EQ(bits.size(), size_t(PRIM_KIND_COUNT + LIGHT_KIND_COUNT + MATERIAL_KIND_COUNT));
    EXPECT_LT(*bits.rbegin(), 32u);
}

TEST(LightArrays, KindPastItsCountIsRefusedNotMappedIntoTheNextGroup) {
    SceneArrays arrays = buildSceneArrays(Scene{});
    gpu::Light light{};
    light.type = LIGHT_KIND_COUNT;  // a kind whose count was not raised
    arrays.lights.push_back(light);
    EXPECT_THROW(sceneFeatures(arrays), std::logic_error);
    arrays.lights.back().type = LIGHT_KIND_COUNT - 1u;
    EXPECT_NO_THROW(sceneFeatures(arrays));
}

TEST(LightArrays, DeltaLightsArePointSpotAndDirectionalOnly) {
    for (uint32_t k = 0; k < LIGHT_KIND_COUNT; ++k)
        EXPECT_EQ(isDeltaLight(k), k == gpu::LIGHT_POINT || k == gpu::LIGHT_SPOT || k == gpu::LIGHT_DIRECTIONAL)
            << "kind " << k;
}

TEST(LightArrays, EnvironmentMapHasItsFeatureBitSizeTablesAndPower) {
    // A 4 x 2 map: the top row 3, the bottom row 1 (each hemisphere 2 pi sr), radiance [2, 1, 1]:
    // mean over solid angle (3 + 1) / 2 = 2 times the factor, mean of RGB (4 + 2 + 2) / 3.
    Scene scene;
    scene.materials.push_back(Material{});
    Light env;
    env.type = LightType::Environment;
    env.intensity = glm::vec3(2, 1, 1);
    auto map = std::make_shared<EnvironmentImage>();
    map->width = 4;
    map->height = 2;
    for (int i = 0; i < 8; ++i) map->texels.push_back(env.intensity * (i < 4 ? 3.0f : 1.0f));
    env.map = map;
    scene.lights.push_back(env);
    SceneArrays arrays = buildSceneArrays(scene);
    ASSERT_EQ(arrays.lights.size(), 1u);
    const gpu::Light& light = arrays.lights[0];
    EXPECT_EQ(light.type, gpu::LIGHT_ENVIRONMENT);
    EXPECT_EQ(light.flags, gpu::LIGHT_ENVIRONMENT_MAP);
    EXPECT_EQ(light.first, 4u);
    EXPECT_EQ(light.count, 2u);
    EXPECT_EQ(arrays.environmentTexels.size(), 8u);
    EXPECT_EQ(arrays.environmentTexels[0], glm::vec4(6, 3, 3, 0));
    EXPECT_EQ(arrays.environmentTable.size(), 8u);
    const double pi = std::numbers::pi, r = 3.0;
    EXPECT_NEAR(lightPower(light, float(r)), 4 * pi * pi * r * r * (8.0 / 3.0), 1e-2);
    EXPECT_NE(sceneFeatures(arrays) & (1u << FEATURE_ENVIRONMENT_MAP), 0u);
    // A constant sky has neither the bit nor the tables, and its power is unchanged.
    scene.lights[0].map = nullptr;
    SceneArrays constant = buildSceneArrays(scene);
    EXPECT_EQ(sceneFeatures(constant) & (1u << FEATURE_ENVIRONMENT_MAP), 0u);
    EXPECT_TRUE(constant.environmentTexels.empty());
    EXPECT_NEAR(lightPower(constant.lights[0], float(r)), 4 * pi * pi * r * r * (4.0 / 3.0), 1e-2);
    EXPECT_LT(FEATURE_ENVIRONMENT_MAP, 32u);
    EXPECT_GE(FEATURE_ENVIRONMENT_MAP, FEATURE_MATERIAL + MATERIAL_KIND_COUNT);
}

// Whether a quad light is sampled as a spherical rectangle is decided once, on the host: a
// rectangle gets LIGHT_RECTANGLE, and only a scene with some other parallelogram sets the
// feature bit that keeps the two-triangle sampling in the kernel.
TEST(LightArrays, RectangleQuadLightsAreFlaggedAndParallelogramsSetTheirFeatureBit) {
    auto quadLight = [](glm::vec3 edgeU, glm::vec3 edgeV) {
        Shape quad;
        quad.type = ShapeType::Quad;
        quad.emission = glm::vec3(1.0f);
        quad.origin = glm::vec3(-0.5f, 1.0f, -0.5f);
        quad.edgeU = edgeU;
        quad.edgeV = edgeV;
        return quad;
    };
    Scene scene;
    scene.materials.push_back(Material{});
    // Edges written in decimals: orthogonal to within rounding.
    scene.shapes.push_back(quadLight(glm::vec3(0.3f, 0.0f, 0.1f), glm::vec3(-0.1f, 0.0f, 0.3f)));
    SceneArrays rectangles = buildSceneArrays(scene);
    ASSERT_EQ(rectangles.lights.size(), 1u);
    EXPECT_NE(rectangles.lights[0].flags & gpu::LIGHT_RECTANGLE, 0u);
    EXPECT_EQ(sceneFeatures(rectangles) & (1u << FEATURE_PARALLELOGRAM_LIGHT), 0u);
    scene.shapes.push_back(quadLight(glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.2f, 0.0f, 1.0f)));
    SceneArrays mixed = buildSceneArrays(scene);
    ASSERT_EQ(mixed.lights.size(), 2u);
    EXPECT_NE(mixed.lights[0].flags & gpu::LIGHT_RECTANGLE, 0u);
    EXPECT_EQ(mixed.lights[1].flags & gpu::LIGHT_RECTANGLE, 0u);
    EXPECT_NE(sceneFeatures(mixed) & (1u << FEATURE_PARALLELOGRAM_LIGHT), 0u);
    EXPECT_LT(FEATURE_PARALLELOGRAM_LIGHT, 32u);
}
