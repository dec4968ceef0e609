// An equirectangular environment map (SCENE_FORMAT.md `environment` with `file`): the
// contract's radiance lookup (Mitsuba 3's orientation, texels constant over their area) and
// the piecewise-constant distribution that samples it in proportion to texel luminance times
// texel solid angle, with an alias table over texels (O(1) per draw). The GPU sampler is to
// mirror sampleEnvironmentMap / environmentMapPdf here (shaders/lights/environment_map.glsl);
// the tests check these against each other.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "shared/types.h"

namespace penumbra {

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

// The GPU's layout of the texels (binding 14): radiance as RGBA (alpha unused), row by row;
// `out` holds width * height entries (host memory, or a mapped GPU buffer).
void writeEnvironmentTexels(const EnvironmentImage& image, glm::vec4* out);

// Luminance (Rec. 709 / sRGB primaries) times solid angle per texel, as an alias table. A map
// with no emitting texel is sampled uniformly in solid angle (weights = solid angles) so that
// every pdf stays finite; it delivers no light either way.
EnvironmentDistribution buildEnvironmentDistribution(EnvironmentImage image);
// The same distribution's alias table alone, for a map that stays where it is (the scene's):
// no copy of the texels, one array of doubles while it is built. `black`, when given: no
// texel emits.
std::vector<gpu::AliasEntry> buildEnvironmentTable(const EnvironmentImage& image, bool* black = nullptr);

// The slot of an alias draw over `count` entries and its coin, from the 48 bits of two
// uniform numbers of 24 bits each (the GPU's resolution): one 24-bit number reaches only 2^24
// slots, and unevenly for counts that do not divide 2^24 (an 8k x 4k map has 2^25 texels).
uint32_t environmentAliasSlot(glm::dvec2 u, uint32_t count, double* coin);

// Draws a direction: a texel from the alias table with u.x, u.y (environmentAliasSlot, as the
// GPU draws), then uniform in that texel's solid angle (phi uniform in its column's range from
// the coin rescaled within its side, cos theta uniform in its row's range from u.z). `pdf`:
// the solid-angle density, pmf(texel) / solid angle.
glm::dvec3 sampleEnvironmentMap(const EnvironmentDistribution& dist, glm::dvec3 u, double* pdf);

// The solid-angle density of d under sampleEnvironmentMap: pmf of the texel d is looked up
// in, over that texel's solid angle (constant over the texel, consistent with the lookup).
double environmentMapPdf(const EnvironmentDistribution& dist, glm::dvec3 d);

}  // namespace penumbra
