#!/usr/bin/env python3
"""Writes the example glTF model scenes/models/torus_knot.gltf (base64 buffer) and .glb.

A (2,3) torus knot tube, 256 x 16 vertices (8192 triangles) with exact normals, one node
that scales, turns and lifts it onto the floor of scenes/gltf_model.json. Standard library
only, deterministic output, so the committed files can be regenerated and diffed.
Usage: tools/scenes/make_models.py [OUTPUT_DIR]   (default: scenes/models next to this script)
"""
import base64
import json
import math
import os
import struct
import sys
from pathlib import Path


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # tools/: penumbra_tools
from penumbra_tools.vec import add, cross, dot, normalize, scale, sub

SEGMENTS, SIDES, TUBE = 256, 16, 0.45


def knot(t):
    """Torus knot (p, q) = (2, 3): r(t) = 2 + cos(3t), in the xy plane with height -sin(3t)."""
    r = 2.0 + math.cos(3 * t)
    return (r * math.cos(2 * t), r * math.sin(2 * t), -math.sin(3 * t))


def tube_mesh():
    positions, normals, indices = [], [], []
    h = 1e-4
    for i in range(SEGMENTS):
        t = 2 * math.pi * i / SEGMENTS
        p0, pm, pp = knot(t), knot(t - h), knot(t + h)
        tangent = normalize(sub(pp, pm))
        # Frenet frame: the curvature of this knot never vanishes, so the frame is smooth and
        # closes up after one turn (no seam twist, unlike parallel transport).
        curvature = sub(add(pp, pm), scale(p0, 2.0))
        normal = normalize(sub(curvature, scale(tangent, dot(curvature, tangent))))
        binormal = cross(tangent, normal)
        for j in range(SIDES):
            a = 2 * math.pi * j / SIDES
            n = add(scale(normal, math.cos(a)), scale(binormal, math.sin(a)))
            positions.append(add(p0, scale(n, TUBE)))
            normals.append(n)
    for i in range(SEGMENTS):
        for j in range(SIDES):
            a = i * SIDES + j
            b = ((i + 1) % SEGMENTS) * SIDES + j
            c = ((i + 1) % SEGMENTS) * SIDES + (j + 1) % SIDES
            d = i * SIDES + (j + 1) % SIDES
            indices += [a, b, c, a, c, d]
    # glTF front faces are counter-clockwise seen from outside: check one triangle against
    # its outward normal and flip every triangle if needed.
    p = [positions[k] for k in indices[:3]]
    if dot(cross(sub(p[1], p[0]), sub(p[2], p[0])), normals[indices[0]]) < 0:
        for k in range(0, len(indices), 3):
            indices[k + 1], indices[k + 2] = indices[k + 2], indices[k + 1]
    return positions, normals, indices


def build():
    positions, normals, indices = tube_mesh()
    pos_bytes = b"".join(struct.pack("<3f", *p) for p in positions)
    nrm_bytes = b"".join(struct.pack("<3f", *n) for n in normals)
    idx_bytes = struct.pack(f"<{len(indices)}H", *indices)
    blob = pos_bytes + nrm_bytes + idx_bytes
    lo = [min(p[k] for p in positions) for k in range(3)]
    hi = [max(p[k] for p in positions) for k in range(3)]
    turn = math.radians(20.0)
    doc = {
        "asset": {"version": "2.0", "generator": "penumbra tools/scenes/make_models.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        # Scale 0.3 makes the knot about 2 units wide; lifted by its lowest point it rests on
        # y = 0 (the turn about y leaves heights alone).
        "nodes": [{"name": "torus_knot", "mesh": 0, "translation": [0.0, round(-lo[1] * 0.3, 6), 0.0],
                   "rotation": [0.0, math.sin(turn / 2), 0.0, math.cos(turn / 2)], "scale": [0.3, 0.3, 0.3]}],
        "meshes": [{"name": "torus_knot", "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0, "mode": 4}]}],
        "materials": [{"name": "copper", "pbrMetallicRoughness": {
            "baseColorFactor": [0.85, 0.45, 0.2, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": len(normals), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos_bytes), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos_bytes), "byteLength": len(nrm_bytes), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos_bytes) + len(nrm_bytes), "byteLength": len(idx_bytes), "target": 34963},
        ],
        "buffers": [{"byteLength": len(blob)}],
    }
    return doc, blob


def write_gltf(doc, blob, path):
    doc = json.loads(json.dumps(doc))
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(blob).decode("ascii")
    path.write_text(json.dumps(doc, indent=1) + "\n")


def write_glb(doc, blob, path):
    """GLB: 12-byte header, JSON chunk padded with spaces, BIN chunk padded with zeros."""
    text = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    text += b" " * (-len(text) % 4)
    blob += b"\0" * (-len(blob) % 4)
    total = 12 + 8 + len(text) + 8 + len(blob)
    path.write_bytes(struct.pack("<4sII", b"glTF", 2, total) + struct.pack("<II", len(text), 0x4E4F534A) + text +
                     struct.pack("<II", len(blob), 0x004E4942) + blob)


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "scenes" / "models"
    out.mkdir(parents=True, exist_ok=True)
    doc, blob = build()
    write_gltf(doc, blob, out / "torus_knot.gltf")
    write_glb(doc, blob, out / "torus_knot.glb")
    print(f"wrote {out / 'torus_knot.gltf'} and .glb ({doc['accessors'][2]['count'] // 3} triangles)")


if __name__ == "__main__":
    main()
