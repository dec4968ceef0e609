// Triangle meshes from files (SCENE_FORMAT.md "Mesh files"): PLY (ply_reader.cpp) and
// Wavefront OBJ (obj_reader.cpp), told apart by the extension. The readers apply the rules
// of a JSON mesh (limits.h ranges, no zero-area triangle, non-zero normals) with the file's
// own locations in the messages; the scene file's side (`file`, materials, emission) is
// load_json.cpp's.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace penumbra {

// One material's share of a mesh file: a Mesh shape (positions, indices, normals and uvs
// filled in; material and emission left to the caller). OBJ files yield one part per
// `usemtl` name, in order of first use; PLY files and OBJ files without usemtl yield one.
struct MeshPart {
    std::string material;  // the usemtl name in effect ("" before any, and for PLY)
    Shape shape;
};

// Reads `file` (.ply or .obj, case-insensitive; anything else is refused). Throws
// InputError "<label>: line N: why" (OBJ), "<label>: face N: why" / "<label>: header line
// N: why" (PLY), or "<label>: why" for the file as a whole (unreadable, too large, no
// triangles). Texture coordinates are flipped to v' = 1 - v: files write them with v up
// (OpenGL's convention, as Blender exports), Penumbra's v = 0 is the image's top row
// (Mitsuba 3's `flip_tex_coords`, on by default, does the same).
std::vector<MeshPart> readMeshFile(const std::filesystem::path& file, const std::string& label);

// The rules shared with JSON meshes, one home each. Why a triangle may not be used (zero
// or non-finite area), or nothing.
std::optional<std::string> triangleProblem(glm::vec3 a, glm::vec3 b, glm::vec3 c);
// Whether every component is finite and within [-1e8, 1e8] (limits.h).
bool coordinateInRange(glm::vec3 p);
// The unit normal of `n`, or nothing when it has zero or non-finite length.
std::optional<glm::vec3> unitNormal(glm::vec3 n);

namespace mesh_file_detail {
// The readers, for readMeshFile and the fuzzer; `bytes` is the whole file.
std::vector<MeshPart> readPly(const std::string& bytes, const std::string& label);
std::vector<MeshPart> readObj(const std::string& bytes, const std::string& label);
}  // namespace mesh_file_detail

}  // namespace penumbra
