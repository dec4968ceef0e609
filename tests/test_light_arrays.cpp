// The host side of the lights (render/light_arrays.h) and the scene feature bits: every kind
// of primitive, light and material has a bit of its own, and a kind added to types.h without
// raising its *_KIND_COUNT is refused instead of setting another group's bit.
#include <gtest/gtest.h>

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
