// The ranges scene values must lie in (docs/design/contract-decisions.md): what the intersection code and the
// float32 accumulation handle exactly.
// Values outside are refused when loading, never rendered wrongly.
#pragma once

namespace penumbra {

// Positions, sphere radii and quad edges: |x| <= 1e8. The intersection tests square and
// multiply coordinates (ray/sphere: radius^2 and |centre - ray|^2; triangles: triple
// products ~ x^3), so values up to 1e8 keep every intermediate below 1e25, far inside
// float32 (3.4e38); 1e20 would square to infinity and the sphere would never be hit.
constexpr double kMaxCoordinate = 1e8;

// Radiance (emission, environment), intensity and irradiance, also when derived from a
// power: each component <= 1e20. The film sums up to 2^31 samples per pixel in float32:
// 2^31 * 1e20 = 2.1e29 leaves a factor 1e9 below 3.4e38 for the estimators' weights
// (1/pdf of light selection and sampling), so the sum of any pixel stays finite.
constexpr double kMaxRadiometric = 1e20;

}  // namespace penumbra
