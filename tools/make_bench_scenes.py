#!/usr/bin/env python3
"""Writes the large benchmark scene(s) into build/bench/ (not committed: ~35 MB of JSON).

  displaced_1m.json  a displaced, finely tessellated sphere of about 1 million triangles on a
                     floor, lit by one downward-facing quad light; direct integrator (MIS).

Usage: tools/make_bench_scenes.py [--triangles N] [--out DIR]   (run from the repository root)
Standard library only; the file is rewritten only when its parameters changed.
"""
import argparse
import json
import math
import os


def displaced_sphere(triangles):
    """A UV sphere of `rings` x 2*rings quads with a bumpy radius (the same surface as
    penumbra_bench's procedural:N), counter-clockwise seen from outside."""
    rings = 4  # 4 r^2 - 4 r triangles: 2 per quad, 1 per quad in the two polar rows
    while 4 * rings * rings - 4 * rings < triangles:
        rings += 1
    pos = []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        st, ct = math.sin(theta), math.cos(theta)
        for j in range(2 * rings + 1):
            phi = 2 * math.pi * j / (2 * rings)
            r = 0.8 * (1.0 + 0.08 * math.sin(13 * theta) * math.sin(11 * phi) + 0.03 * math.sin(57 * theta + 3 * phi))
            pos += [round(r * st * math.cos(phi), 5), round(0.85 + r * ct, 5), round(r * st * math.sin(phi), 5)]
    idx = []
    w = 2 * rings + 1
    for i in range(rings):
        for j in range(2 * rings):
            a, b, c, d = i * w + j, i * w + j + 1, (i + 1) * w + j, (i + 1) * w + j + 1
            # Outward facing: (b - a) x (c - a) points away from the centre for this ordering.
            if i > 0:
                idx += [a, b, c]
            if i < rings - 1:
                idx += [b, d, c]
    return pos, idx


def displaced_1m(triangles):
    pos, idx = displaced_sphere(triangles)
    return {
        "camera": {"eye": [0, 1.5, 3.6], "target": [0, 0.8, 0], "up": [0, 1, 0], "fov_y": 40},
        "film": {"width": 512, "height": 384},
        "sampler": {"spp": 16},
        "integrator": {"type": "direct", "strategy": "mis"},
        "materials": {
            "floor": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
            "clay": {"type": "diffuse", "albedo": [0.75, 0.6, 0.45]},
        },
        "shapes": [
            {"type": "quad", "origin": [-5, 0, -5], "edge_u": [0, 0, 10], "edge_v": [10, 0, 0], "material": "floor"},
            {"type": "mesh", "positions": pos, "indices": idx, "material": "clay"},
            # edge_u x edge_v = (1,0,0) x (0,0,1) = (0,-1,0): emits downwards
            {"type": "quad", "origin": [-0.5, 2.6, -0.2], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1],
             "emission": [12, 11, 9]},
        ],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--triangles", type=int, default=1_000_000)
    ap.add_argument("--out", default="build/bench")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "displaced_1m.json")
    stamp = path + ".params"
    key = f"displaced_1m v2 triangles={args.triangles}"
    if os.path.exists(path) and os.path.exists(stamp) and open(stamp).read() == key:
        print(path)
        return
    scene = displaced_1m(args.triangles)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(scene, f, separators=(",", ":"))
    os.replace(tmp, path)
    with open(stamp, "w") as f:
        f.write(key)
    print(path)


if __name__ == "__main__":
    main()
