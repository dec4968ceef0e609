// The film's accumulation at huge sample counts (shared/types.h, AccumSum): a 1x1 film
// under a constant sky of 0.3, where every sample is exactly 0.3f, must give 0.3f to float
// rounding at any spp. A plain float32 sum and count gave 0.300147 at 2^20 spp, 0.27376 at
// 2^24 and 0.5 at 2^25. The tolerance is the error bound of Kahan's summation (Higham,
// "Accuracy and Stability of Numerical Algorithms", 2nd ed., eq. 4.8: |error| <=
// (2u + O(n u^2)) sum |x_i|, u = 2^-24) plus the readback's rounding of the mean, so a
// regression to a plain sum fails by orders of magnitude.
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "render/renderer.h"
#include "render_helpers.h"

using namespace penumbra;
using nlohmann::json;

namespace {

json constantSky(uint32_t spp) {
    return {
        {"camera", {{"eye", {0, 0, 0}}, {"target", {0, 0, -1}}, {"up", {0, 1, 0}}, {"fov_y", 40}}},
        {"film", {{"width", 1}, {"height", 1}}},
        {"sampler", {{"spp", spp}, {"seed", 3}}},
        {"integrator", {{"type", "direct"}, {"strategy", "mis"}}},
        {"shapes", json::array()},
        {"lights", json::array({{{"type", "environment"}, {"radiance", {0.3, 0.3, 0.3}}}})},
    };
}

}  // namespace

TEST(AccumulationPrecision, ConstantSkyIsExactAtHugeSpp) {
    const double u = std::ldexp(1.0, -24);  // float32's unit roundoff
    for (uint32_t spp : {1u, 3u, 1u << 20, 1u << 22, 1u << 24, (1u << 24) + 1, 1u << 25}) {
        SCOPED_TRACE(testing::Message() << spp << " spp");
        const Scene scene = test::sceneFromJson(constantSky(spp), "accumulation-precision");
        Renderer renderer(test::gpuContext(), scene);
        renderer.renderAll();
        const auto pixel = renderer.accumulation().read<gpu::AccumSum>().at(0);
        EXPECT_EQ(pixel.count, spp) << "every sample counted, exactly";
        const Image image = renderer.readback(0.0);
        const double bound = (2 * u + double(spp) * u * u + u) * 0.3f;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(image.rgb[c], 0.3f, bound) << "channel " << c;
    }
}
