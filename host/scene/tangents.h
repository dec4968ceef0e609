// Per-vertex tangent frames for normal-mapped meshes (glTF normalTexture): the tangent that
// points along increasing u on the surface, and the sign w that says which way the
// bitangent B = w cross(N, T) points (glTF 2.0 section 3.7.2.1, TANGENT).
#pragma once

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace penumbra {

// Fills mesh `s`'s tangents from its positions, uvs and normals (the face normal where it has
// none), for a file without TANGENT. glTF asks for MikkTSpace (Mikkelsen 2008, "Simulation of
// Wrinkled Surfaces Revisited"); this follows its construction per corner: each triangle's
// uv-gradient tangent and bitangent (Lengyel 2001, "Computing Tangent Space Basis Vectors for
// an Arbitrary Mesh") are projected into the plane of the corner's normal, normalized and
// weighted by the corner's angle, summed per vertex, then made orthogonal to the vertex normal
// (Gram-Schmidt), with w the sign of the summed bitangent against cross(N, T). The bitangent
// is -dp/dv: glTF's v grows downwards in the image, and a normal map's +Y (green) points up
// (the sample viewer's B = cross(N, T) for a plain mapping, w = +1). Where it
// differs from MikkTSpace: vertices are not split where their corners disagree in
// handedness or direction (MikkTSpace gives such a vertex one tangent per group), so at uv
// mirror seams the tangent is the blend of both sides. On the planar, consistently mapped
// surfaces a tangent-space bake is usually made for, both give the same frame. Triangles
// with degenerate uvs (zero uv area) add nothing; a vertex left with no tangent gets one
// perpendicular to its normal (any: its normal map has no defined frame), never NaN.
void computeTangents(Shape& s);

// An arbitrary unit vector perpendicular to unit `n` (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited").
glm::vec3 perpendicularTo(glm::vec3 n);

}  // namespace penumbra
