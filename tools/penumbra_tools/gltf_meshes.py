"""The triangle meshes of a glTF 2.0 file (.gltf with data: or file buffers, or .glb), with
their node transforms applied and their metallic-roughness factors, as plain numpy arrays:
what tools/penumbra_tools/mitsuba_penumbra.py needs of a `gltf` shape (docs/SCENE_FORMAT.md, "glTF input").
A reader for trusted files of the project, not a validator: Penumbra's own loader
(host/scene/load_gltf.cpp) checks its input. Files with textures or KHR_lights_punctual
lights raise NotImplementedError; cameras are ignored (as Penumbra ignores a `gltf` shape's);
degenerate triangles are kept (Penumbra drops them; they add nothing to the image)."""
import base64
import json
import os
import struct

import numpy as np

_COMPONENTS = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
# glTF 2.0 section 3.11: normalized integers map to [0, 1] (unsigned) or [-1, 1] (signed).
_NORM = {5120: 127.0, 5121: 255.0, 5122: 32767.0, 5123: 65535.0, 5125: 4294967295.0}


def _load(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":  # GLB: 12-byte header, then chunks (JSON first, then BIN)
        off, doc, binary = 12, None, None
        while off + 8 <= len(data):
            n, kind = struct.unpack_from("<II", data, off)
            chunk = data[off + 8: off + 8 + n]
            if kind == 0x4E4F534A:
                doc = json.loads(chunk)
            elif kind == 0x004E4942:
                binary = chunk
            off += 8 + n
        return doc, binary
    return json.loads(data), None


def _buffers(doc, folder, glb_bin):
    out = []
    for b in doc.get("buffers", []):
        uri = b.get("uri")
        if uri is None:
            out.append(glb_bin)
        elif uri.startswith("data:"):
            out.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            with open(os.path.join(folder, uri), "rb") as f:
                out.append(f.read())
    return out


def _accessor(doc, bufs, i):
    a = doc["accessors"][i]
    dtype = np.dtype(_COMPONENTS[a["componentType"]])
    width, count = _WIDTH[a["type"]], a["count"]
    bv = doc["bufferViews"][a["bufferView"]]
    buf = bufs[bv["buffer"]]
    start = bv.get("byteOffset", 0) + a.get("byteOffset", 0)
    stride = bv.get("byteStride", dtype.itemsize * width)
    rows = np.ndarray((count, width), dtype=dtype, buffer=buf, offset=start, strides=(stride, dtype.itemsize))
    out = rows.astype(np.float64)
    if a.get("normalized"):
        out = out / _NORM[a["componentType"]]
        if dtype.kind == "i":
            out = np.maximum(out, -1.0)
    return out


def _local(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major
    t = np.array(node.get("translation", [0, 0, 0]), dtype=np.float64)
    x, y, z, w = np.array(node.get("rotation", [0, 0, 0, 1]), dtype=np.float64) / \
        max(np.linalg.norm(node.get("rotation", [0, 0, 0, 1])), 1e-300)
    # Unit quaternion (x, y, z, w) to a rotation matrix (Shoemake 1985).
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = np.eye(4)
    m[:3, :3] = r * np.array(node.get("scale", [1, 1, 1]), dtype=np.float64)
    m[:3, 3] = t
    return m


def material_factors(doc, index):
    """(base_color, metallic, roughness, emission) of material `index` (glTF defaults 1),
    or None for a primitive without a material."""
    if index is None:
        return None
    mat = doc["materials"][index]
    pbr = mat.get("pbrMetallicRoughness", {})
    base = [min(float(c), 1.0) for c in pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]]
    emission = [float(c) for c in mat.get("emissiveFactor", [0, 0, 0])]
    strength = mat.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
    return (base, float(pbr.get("metallicFactor", 1.0)), float(pbr.get("roughnessFactor", 1.0)),
            [e * float(strength) for e in emission], bool(mat.get("doubleSided", False)))


def read_gltf(path, to_world=None):
    """[(positions N x 3, indices M x 3, normals N x 3 or None, material factors or None)] of
    every triangle primitive (mode 4) of the default scene's node trees; to_world (4 x 4)
    applies on top of the node transforms."""
    doc, glb_bin = _load(path)
    # What Penumbra reads but this reader does not: refused, never silently dropped.
    if "KHR_lights_punctual" in doc.get("extensionsUsed", []):
        raise NotImplementedError("glTF KHR_lights_punctual lights")
    for m in doc.get("materials", []):
        pbr = m.get("pbrMetallicRoughness", {})
        if "baseColorTexture" in pbr or "metallicRoughnessTexture" in pbr or "emissiveTexture" in m:
            raise NotImplementedError("glTF material textures")
    bufs = _buffers(doc, os.path.dirname(path), glb_bin)
    out = []
    scenes = doc.get("scenes", [])
    roots = scenes[doc.get("scene", 0)]["nodes"] if scenes else range(len(doc.get("nodes", [])))
    stack = [(r, np.eye(4) if to_world is None else np.asarray(to_world, dtype=np.float64)) for r in roots]
    while stack:
        ni, parent = stack.pop()
        node = doc["nodes"][ni]
        world = parent @ _local(node)
        stack.extend((c, world) for c in node.get("children", []))
        if "mesh" not in node:
            continue
        lin = world[:3, :3]
        mirrored = np.linalg.det(lin) < 0
        for prim in doc["meshes"][node["mesh"]]["primitives"]:
            if prim.get("mode", 4) != 4 or "POSITION" not in prim["attributes"]:
                continue
            p = _accessor(doc, bufs, prim["attributes"]["POSITION"])
            p = p @ lin.T + world[:3, 3]
            idx = _accessor(doc, bufs, prim["indices"]).astype(np.int64).reshape(-1, 3) if "indices" in prim \
                else np.arange(len(p)).reshape(-1, 3)
            if mirrored:  # keep the winding (the geometric normal's side) after a reflection
                idx = idx[:, [0, 2, 1]]
            n = None
            if "NORMAL" in prim["attributes"]:
                n = _accessor(doc, bufs, prim["attributes"]["NORMAL"]) @ np.linalg.inv(lin)  # inverse transpose
                n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
            out.append((p, idx, n, material_factors(doc, prim.get("material"))))
    return out
