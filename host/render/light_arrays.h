// Lights -> GPU: the gpu::Light of each light (lights without geometry, and the emitting
// shapes buildSceneArrays meets), the mesh lights' triangle tables, and the light-selection
// tables. Whether a light is a delta light, and its power for light selection, are decided
// here and nowhere else.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"
#include "shared/types.h"

namespace penumbra {

struct SceneArrays;
enum class EnvironmentTexels;

// Point, spot and directional lights (every light with a single direction per point):
// sampled explicitly, never hit by a ray (SCENE_FORMAT.md, "direct").
bool isDeltaLight(uint32_t type);

// Power (mean of RGB, watts) used for light selection "power" (SCENE_FORMAT.md): area
// lights pi * Le * area (twice for two-sided), points 4 pi I, spots I spotFalloffIntegral (scene.h), directional pi R^2 E and the
// environment 4 pi^2 R^2 L for the scene's bounding radius R (as pbrt-v4 does; for a map, L is
// its mean radiance over solid angle).
double lightPower(const gpu::Light& light, float sceneRadius);

// Appends the lights that have no geometry (point, spot, directional; several environments merged
// into one, whose index becomes out.environmentLight), in scene order. An environment map's
// texels (unless left out) and sampling table go to out.environmentTexels and
// out.environmentTable.
void appendLightsWithoutGeometry(const std::vector<Light>& lights, SceneArrays& out,
                                 EnvironmentTexels environmentTexels);

// The gpu::Light of an emitting sphere or quad whose primitive has input index `primitive`,
// and of an emitting mesh of total area `area` (its triangle table follows in
// finishLightArrays).
gpu::Light makeSphereLight(const Shape& shape, uint32_t primitive);
gpu::Light makeQuadLight(const Shape& shape, uint32_t primitive);
gpu::Light makeMeshLight(const Shape& shape, double area);

// The emitting triangles of one mesh light, by input primitive index, with their areas.
struct MeshLightTriangles {
    uint32_t light;
    std::vector<uint32_t> prims;
    std::vector<double> areas;
};

// Once the BVH has ordered the primitives (leafIndex: input index -> leaf-order index):
// points the area lights at their leaf-order primitives and builds the mesh lights'
// area-proportional triangle tables (lecture, "Mesh Lights").
void finishAreaLights(const std::vector<uint32_t>& leafIndex, std::vector<MeshLightTriangles>& meshLights,
                      SceneArrays& out);

// The light-selection table over all lights, then its delta-only and continuous-only
// sub-tables built from the same weights (RenderParams in shaders/shared/types.h); sets each
// light's selectionProb. Needs out.boundsRadius for the power of lights at infinity. Under
// "bvh" these tables are the power ones: the tree (render/light_bvh_arrays.h) replaces only
// the full table's draws, those of the light and mis strategies.
void buildLightSelection(LightSelection selection, SceneArrays& out);

}  // namespace penumbra
