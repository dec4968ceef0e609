#!/usr/bin/env python3
"""Writes the instancing benchmark into build/bench/ (not committed: the PLY is ~2 MB).

  rock_100k.ply        a bumpy sphere of radius 0.5 with about 100k triangles (binary PLY)
  instances_N.json     N instances of it (a group of one mesh file) on a floor under a quad
                       light: the two-level BVH (SCENE_FORMAT.md "instance")
  flattened_N.json     the same first N placements written out as N mesh-file shapes with the
                       same to_world: the triangles copied, for the speed comparison

Usage: tools/scenes/make_instances_scene.py [--instances N ...] [--flattened N ...] [--out DIR]
(run from the repository root). Standard library only. The placements are a grid of rows
of 40, each turned about +y and scaled by a fixed sequence, so that every file is the same
from run to run.
"""
import argparse
import json
import math
import os
import struct

ROWS = 40  # instances per row of the grid
SPACING = 1.25


def write_rock(path, bands=158):
    """A sphere of diameter 1 resting on y = 0, `bands` latitude bands of 2 bands quads,
    displaced by a few sines: 4 bands (bands - 1) triangles (the poles' bands are fans),
    99,224 for 158 bands. Returns the triangle count."""
    lon = 2 * bands
    verts = []
    for i in range(bands + 1):
        theta = math.pi * i / bands
        for j in range(lon):
            phi = 2 * math.pi * j / lon
            r = 0.5 * (1 + 0.06 * math.sin(7 * theta) * math.cos(5 * phi) + 0.03 * math.sin(13 * phi + 3 * theta))
            verts.append((r * math.sin(theta) * math.cos(phi), 0.5 + r * math.cos(theta),
                          r * math.sin(theta) * math.sin(phi)))
    faces = []
    for i in range(bands):
        for j in range(lon):
            a, b = i * lon + j, i * lon + (j + 1) % lon
            c, d = a + lon, b + lon
            if i > 0:
                faces.append((a, b, c))
            if i < bands - 1:
                faces.append((b, d, c))
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                 "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
                 % (len(verts), len(faces))).encode())
        f.write(b"".join(struct.pack("<3f", *v) for v in verts))
        f.write(b"".join(struct.pack("<B3i", 3, *t) for t in faces))
    return len(faces)


def placement(k):
    """The to_world of placement k: scale, a turn about +y, a place on the grid."""
    scale = 0.8 + 0.4 * ((k * 37) % 101) / 100
    angle = (k * 47) % 360
    x, z = (k % ROWS - ROWS / 2) * SPACING, (k // ROWS) * SPACING
    return {"scale": round(scale, 4), "rotate": {"axis": [0, 1, 0], "angle": angle}, "translate": [x, 0, -z]}


def scene(shapes, count):
    depth = (count + ROWS - 1) // ROWS * SPACING
    return {
        "camera": {"eye": [0, 12, 8], "target": [0, 0, -depth / 3], "up": [0, 1, 0], "fov_y": 50},
        "film": {"width": 256, "height": 192},
        "sampler": {"spp": 4, "seed": 0},
        "integrator": {"type": "direct", "strategy": "mis"},
        "materials": {"rock": {"type": "diffuse", "albedo": [0.6, 0.55, 0.5]},
                      "floor": {"type": "diffuse", "albedo": 0.5}},
        "shapes": [{"type": "quad", "origin": [-40, 0, 20], "edge_u": [80, 0, 0], "edge_v": [0, 0, -120],
                    "material": "floor"},
                   {"type": "quad", "origin": [-20, 30, 10], "edge_u": [0, 0, -60], "edge_v": [40, 0, 0],
                    "emission": 3}] + shapes,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--instances", type=int, nargs="*", default=[1000])
    parser.add_argument("--flattened", type=int, nargs="*", default=[50])
    parser.add_argument("--out", default=os.path.join("build", "bench"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    triangles = write_rock(os.path.join(args.out, "rock_100k.ply"))
    for n in args.instances:
        group = {"type": "group", "name": "rock",
                 "shapes": [{"type": "mesh", "file": "rock_100k.ply", "material": "rock"}]}
        shapes = [group] + [{"type": "instance", "of": "rock", "to_world": placement(k)} for k in range(n)]
        with open(os.path.join(args.out, "instances_%d.json" % n), "w") as f:
            json.dump(scene(shapes, n), f, indent=1)
    for n in args.flattened:
        shapes = [{"type": "mesh", "file": "rock_100k.ply", "material": "rock", "to_world": placement(k)}
                  for k in range(n)]
        with open(os.path.join(args.out, "flattened_%d.json" % n), "w") as f:
            json.dump(scene(shapes, n), f, indent=1)
    print("rock_100k.ply: %d triangles" % triangles)


if __name__ == "__main__":
    main()
