#!/usr/bin/env python3
"""Writes the scene of docs/figures/gltf_features.png into OUTPUT_DIR (tools/figures/figures runs it).

Debian's assimp-testmodels TextureTransformTest (KHR_texture_transform) and ClearCoatTest
(emissive textured labels, normal-mapped ribs) are copied beside the scene, since a scene's files must lie in its
folder, with a hand-made alpha-masked model (alphaMode MASK: a leaf-like checkerboard of
holes over a floor, casting a cut-out shadow). The two assimp models that are not in
Debian's package (NormalTangentTest, AlphaBlendModeTest) are stood in for by that model.
Standard library only, deterministic output.
Usage: tools/scenes/make_gltf_features.py OUTPUT_DIR
"""
import base64
import json
import shutil
import struct
import sys
import zlib
from pathlib import Path

ASSIMP = Path("/usr/share/assimp/models/glTF2")


def png_rgba(width, height, pixels):
    """An 8-bit RGBA PNG of rows of (r, g, b, a) tuples."""
    raw = b"".join(b"\0" + bytes(c for px in row for c in px) for row in pixels)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


def masked_quad():
    """A unit quad in the xy plane (facing +z), green, with an 8 x 8 checkerboard of holes."""
    cells = 8
    pixels = [[(40, 160, 60, 0 if (i + j) % 2 == 0 else 255) for i in range(cells)] for j in range(cells)]
    positions = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]
    uvs = [0, 1, 1, 1, 1, 0, 0, 0]
    indices = [0, 1, 2, 0, 2, 3]
    blob = struct.pack("<12f", *positions) + struct.pack("<8f", *uvs) + struct.pack("<6I", *indices)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{
            "alphaMode": "MASK",
            "doubleSided": True,
            "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0, "roughnessFactor": 0.8},
        }],
        "samplers": [{"wrapS": 33071, "wrapT": 33071, "magFilter": 9729}],
        "textures": [{"source": 0, "sampler": 0}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(png_rgba(cells, cells, pixels)).decode()}],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 24},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"},
        ],
    }
    return json.dumps(doc, indent=1)


def scene():
    """Three panels side by side along x, seen head-on, under a sky and a sun."""
    return {
        "camera": {"eye": [0, 0.2, 9], "target": [0, 0.2, 0], "up": [0, 1, 0], "fov_y": 24},
        "film": {"width": 720, "height": 280},
        "sampler": {"spp": 64},
        "materials": {"floor": {"type": "diffuse", "albedo": 0.6}},
        "shapes": [
            {"type": "gltf", "file": "TextureTransformTest.gltf", "to_world": {"translate": [-2.4, 0.15, 0]}},
            {"type": "gltf", "file": "ClearCoatTest.gltf",
             "to_world": {"translate": [1.25, 0.12, 0], "scale": 0.26}},
            {"type": "gltf", "file": "masked_quad.gltf",
             "to_world": {"translate": [2.7, -0.75, 0.6], "rotate": {"axis": [1, 0, 0], "angle": -60}, "scale": 1.4}},
            {"type": "quad", "origin": [2.3, -1.2, 2], "edge_u": [2.4, 0, 0], "edge_v": [0, 0, -2.5],
             "material": "floor"},
        ],
        "lights": [
            {"type": "environment", "radiance": 0.6},
            {"type": "directional", "direction": [-0.3, -1, -0.4], "irradiance": 2.5},
        ],
    }


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "build/gltf_features")
    out.mkdir(parents=True, exist_ok=True)
    for model in ("textureTransform", "ClearCoat-glTF"):
        for f in (ASSIMP / model).iterdir():
            shutil.copy(f, out / f.name)
    (out / "masked_quad.gltf").write_text(masked_quad() + "\n")
    (out / "scene.json").write_text(json.dumps(scene(), indent=1) + "\n")


if __name__ == "__main__":
    main()
