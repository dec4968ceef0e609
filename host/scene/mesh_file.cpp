// readMeshFile's dispatch by extension and the mesh rules shared with JSON meshes (see
// mesh_file.h); the formats themselves are ply_reader.cpp's and obj_reader.cpp's.
#include "scene/mesh_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/errors.h"
#include "core/input_file.h"
#include "scene/limits.h"

namespace penumbra {

std::vector<MeshPart> readMeshFile(const std::filesystem::path& file, const std::string& label) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".ply" && ext != ".obj")
        throwInputError(label, "", "not a mesh file (a mesh \"file\" ends in .ply or .obj)");
    // The bound of glTF models: a 2 GiB file holds ~60M triangles as binary PLY.
    const std::string bytes = readInputFile(file, label, kMaxModelFileBytes);
    return ext == ".ply" ? mesh_file_detail::readPly(bytes, label) : mesh_file_detail::readObj(bytes, label);
}

std::optional<std::string> triangleProblem(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const float area = 0.5f * glm::length(glm::cross(b - a, c - a));
    if (!(area > 0.0f) || !std::isfinite(area)) return std::string("triangle has zero or non-finite area");
    return std::nullopt;
}

bool coordinateInRange(glm::vec3 p) {
    for (int c = 0; c < 3; ++c)
        if (!(std::fabs(p[c]) <= float(kMaxCoordinate))) return false;  // NaN fails too
    return true;
}

std::optional<glm::vec3> unitNormal(glm::vec3 n) {
    const float len = glm::length(n);
    if (!(len > 0.0f) || !std::isfinite(len)) return std::nullopt;
    return n / len;
}

}  // namespace penumbra
