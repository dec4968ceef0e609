// Per-shape transforms (SCENE_FORMAT.md "to_world"): an affine map read from JSON, applied
// to a shape's data when the scene loads, so the GPU only ever sees world-space shapes.
// Points go through the map, edges through its linear part, normals through the inverse
// transpose of that (then normalized).
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "scene/json_reader.h"
#include "scene/scene.h"

namespace penumbra {

// x' = linear x + translation, in double so that composing rotation and scale rounds once.
struct Affine {
    glm::dmat3 linear{1.0};
    glm::dvec3 translation{0.0};
};

// `r` is the to_world value: 4 rows of 4 numbers (row-major, last row 0 0 0 1), or
// {"scale": s | [x, y, z], "rotate": {"axis": [..], "angle": degrees}, "translate": [..]},
// each optional, applied as scale, then rotate, then translate. Fails on `r` (or the
// member at fault) when malformed, not invertible or not finite.
Affine readToWorld(const JsonReader& r);

// |s| when the linear part is s times a rotation (or a reflection): what a sphere allows.
std::optional<double> uniformScaleOf(const Affine& m);
// Whether the linear part is a positive multiple of the identity (no rotation or mirror).
bool turnsNothing(const Affine& m);

glm::vec3 transformPoint(const Affine& m, glm::vec3 p);
glm::vec3 transformVector(const Affine& m, glm::vec3 v);

// Whether the map mirrors (negative determinant): it would turn counter-clockwise
// triangles clockwise, and edge_u x edge_v against the moved surface's front.
bool mirrors(const Affine& m);

// A mesh shape's positions and normals, in place; uvs stay with their vertices. A mirroring
// map also reverses each triangle's winding, so that the front face is the image of the
// front face (as the normals are), as pbrt and Mitsuba keep it.
void transformMesh(const Affine& m, Shape& s);

// A quad's origin and edges, in place. A mirroring map starts the quad at the image of
// origin + edge_u and runs edge_u backwards, so that edge_u x edge_v (the front, which a
// one-sided quad light emits from) is the image of the front; s then runs from the other
// end (a texture on a mirrored quad reads the right way round, not mirrored).
void transformQuad(const Affine& m, Shape& s);

// A glTF model's punctual light under its shape's to_world, as the file's node transforms
// move it: the position as a point, the direction as a vector, then normalized (cone angles
// and intensity unchanged, as glTF defines for node scale).
void transformLight(const Affine& m, Light& light);

}  // namespace penumbra
