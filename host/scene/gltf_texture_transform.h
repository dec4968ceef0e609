// glTF's KHR_texture_transform on a textureInfo: offset, rotation and scale as the uv
// transform a MaterialTexture carries (scene.h, UvTransform), and the texCoord override.
// The GPU applies the transform before the lookup (textures/textures.glsl); which uv set
// is read is gltf_textures.cpp's.
#pragma once

#include <string>

#include <tiny_gltf.h>

#include "scene/scene.h"

namespace penumbra {

struct GltfTextureTransform {
    UvTransform uv;    // identity without the extension
    int texCoord = 0;  // the extension's texCoord if given, else the textureInfo's
};

// Reads `info`'s KHR_texture_transform (path: the textureInfo's JSON path, for errors).
// offset and scale must be two finite numbers, rotation (radians) one, each of magnitude at
// most 1e8; texCoord a non-negative integer. Throws InputError "<label>: <path>.extensions.
// KHR_texture_transform.<key>: ..." otherwise.
GltfTextureTransform readTextureTransform(const tinygltf::TextureInfo& info, const std::string& label,
                                          const std::string& path);
// The same for normalTexture and occlusionTexture, whose textureInfo types differ.
GltfTextureTransform readTextureTransform(const tinygltf::ExtensionMap& extensions, int texCoord,
                                          const std::string& label, const std::string& path);

}  // namespace penumbra
