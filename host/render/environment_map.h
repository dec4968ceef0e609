// An equirectangular environment map (SCENE_FORMAT.md `environment` with `file`): the
// contract's radiance lookup (Mitsuba 3's orientation, texels constant over their area) and
// the piecewise-constant distribution that samples it in proportion to texel luminance times
// texel solid angle, with an alias table over texels (O(1) per draw). The GPU sampler is to
// mirror sampleEnvironmentMap / environmentMapPdf here; the tests check these against each other.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "shared/types.h"

namespace penumbra {

// Linear RGB radiance, row 0 at the top (+y), `width` columns around the vertical axis.
struct EnvironmentImage {
    uint32_t width = 0, height = 0;
    std::vector<glm::vec3> texels;  // width * height, row by row
};

struct EnvironmentDistribution {
    EnvironmentImage image;
    std::vector<gpu::AliasEntry> table;  // one entry per texel; item = texel index
    bool black = false;                  // no texel emits: sampled uniformly in solid angle
};

// The texel (column, row) that radiance from unit direction d (pointing away from the scene)
// is read from: u = atan2(d.x, -d.z) / (2 pi) wrapped to [0, 1), v = acos(d.y) / pi, column
// floor(u W), row floor(v H), both clamped to the image.
glm::uvec2 environmentTexel(glm::dvec3 d, uint32_t width, uint32_t height);

// Solid angle of a texel of row `row`: (2 pi / W) (cos theta_row - cos theta_row+1),
// theta = pi row / H.
double environmentTexelSolidAngle(uint32_t row, uint32_t width, uint32_t height);

glm::vec3 environmentMapRadiance(const EnvironmentImage& image, glm::dvec3 d);

// Luminance (Rec. 709 / sRGB primaries) times solid angle per texel, as an alias table. A map
// with no emitting texel is sampled uniformly in solid angle (weights = solid angles) so that
// every pdf stays finite; it delivers no light either way.
EnvironmentDistribution buildEnvironmentDistribution(EnvironmentImage image);

// Draws a direction: a texel from the alias table with u.x (slot and coin, as the GPU draws),
// then uniform in that texel's solid angle (phi uniform in its columns' range, cos theta
// uniform in its row's range). `pdf`: the solid-angle density, pmf(texel) / solid angle.
glm::dvec3 sampleEnvironmentMap(const EnvironmentDistribution& dist, glm::dvec3 u, double* pdf);

// The solid-angle density of d under sampleEnvironmentMap: pmf of the texel d is looked up
// in, over that texel's solid angle (constant over the texel, consistent with the lookup).
double environmentMapPdf(const EnvironmentDistribution& dist, glm::dvec3 d);

}  // namespace penumbra
