// Internal to host/scene: reads one glTF 2.0 file (.gltf or .glb) into Penumbra shapes,
// materials and lights with node transforms applied. How the result joins a Scene (the
// `gltf` shape's material/emission overrides, the camera of a model rendered on its own)
// is load_json.cpp's.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace penumbra {

struct GltfImport {
    // Mesh shapes, one per triangle primitive, and for each the index of its material in
    // `materials` below, or -1 for a primitive without one (it gets the scene's default).
    std::vector<Shape> shapes;
    std::vector<int> shapeMaterials;
    std::vector<Material> materials;  // one pbr material per glTF material
    std::vector<Texture> textures;    // the materials' textures (MaterialTexture::texture indexes this)
    std::vector<Light> lights;        // KHR_lights_punctual point and directional lights
    std::optional<Camera> camera;     // the first perspective camera in the node hierarchy
    std::vector<std::string> notes;   // skipped primitives, degenerate triangles, ...
};

// Throws InputError("<label>: <glTF JSON path>: <why>") or "<label>: <tinygltf error>";
// `label` is the file as the user should see it.
GltfImport importGltf(const std::filesystem::path& file, const std::string& label);

}  // namespace penumbra
