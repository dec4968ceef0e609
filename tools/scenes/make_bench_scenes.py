#!/usr/bin/env python3
"""Writes the benchmark scenes into build/bench/ (not committed: ~35 MB of JSON).

  displaced_1m.json  a displaced, finely tessellated sphere of about 1 million triangles on a
                     floor, lit by one downward-facing quad light; direct integrator (MIS).
  sphere_room.json   a closed diffuse room of six quads lit by three sphere lights of radii 0.08,
                     0.3 and 0.6, 128x128 at 256 spp; direct integrator with its defaults
                     (MIS, solid-angle sphere sampling): the scene on which Penumbra trailed
                     Mitsuba 3 (docs/performance-history/round-29.md).

Usage: tools/scenes/make_bench_scenes.py [--triangles N] [--out DIR]   (run from the repository root)
Standard library only. The mesh comes from build/penumbra_bench --write-mesh, its one
definition; the file is rewritten when its parameters changed or penumbra_bench is newer.
"""
import argparse
import json
import os
import subprocess
import sys

PENUMBRA_BENCH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "penumbra_bench")


def displaced_sphere(triangles, tmp_path):
    """The displaced sphere of penumbra_bench's procedural:N (defined there only), about
    `triangles` triangles: (positions, indices)."""
    if not os.path.exists(PENUMBRA_BENCH):
        sys.exit(f"make_bench_scenes: {PENUMBRA_BENCH} not found; build Penumbra first (tools/setup)")
    subprocess.run([PENUMBRA_BENCH, "--write-mesh", str(triangles), tmp_path], check=True)
    with open(tmp_path) as f:
        mesh = json.load(f)
    os.remove(tmp_path)
    return mesh["positions"], mesh["indices"]


def displaced_1m(triangles, tmp_path):
    pos, idx = displaced_sphere(triangles, tmp_path)
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


def sphere_room():
    """A closed room of six diffuse quads, 4 wide, 3 high, 4 deep, seen from inside near its
    front wall, and three sphere emitters
    of radii 0.08 (small and bright, near the ceiling), 0.3 (mid-air) and 0.6 (on the floor),
    the emission chosen so that each delivers a similar share of the light."""
    def quad(origin, edge_u, edge_v, material):
        return {"type": "quad", "origin": origin, "edge_u": edge_u, "edge_v": edge_v, "material": material}

    return {
        "camera": {"eye": [0, 1.5, 1.9], "target": [0, 1.2, -2], "up": [0, 1, 0], "fov_y": 60},
        "film": {"width": 128, "height": 128},
        "sampler": {"spp": 256},
        "integrator": {"type": "direct"},
        "materials": {
            "white": {"type": "diffuse", "albedo": [0.73, 0.73, 0.73]},
            "red": {"type": "diffuse", "albedo": [0.63, 0.06, 0.05]},
            "green": {"type": "diffuse", "albedo": [0.14, 0.45, 0.09]},
        },
        # Each quad's edge_u x edge_v points into the room (one-sided lights only care, but
        # the normals are kept consistent).
        "shapes": [
            quad([-2, 0, -2], [0, 0, 4], [4, 0, 0], "white"),   # floor, normal +y
            quad([-2, 3, -2], [4, 0, 0], [0, 0, 4], "white"),   # ceiling, normal -y
            quad([-2, 0, -2], [4, 0, 0], [0, 3, 0], "white"),   # back wall, normal +z
            quad([-2, 0, -2], [0, 3, 0], [0, 0, 4], "red"),     # left wall, normal +x
            quad([2, 0, -2], [0, 0, 4], [0, 3, 0], "green"),    # right wall, normal -x
            quad([-2, 0, 2], [0, 3, 0], [4, 0, 0], "white"),    # front wall, behind the camera, normal -z
            {"type": "sphere", "center": [-1.2, 2.2, -1.0], "radius": 0.08, "emission": [300, 280, 240]},
            {"type": "sphere", "center": [0.9, 1.6, -0.6], "radius": 0.3, "emission": [18, 16, 13]},
            {"type": "sphere", "center": [-0.2, 0.6, -0.9], "radius": 0.6, "emission": [3.2, 3.6, 4.4]},
        ],
    }


def write_json(path, scene):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(scene, f, indent=1)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--triangles", type=int, default=1_000_000)
    ap.add_argument("--out", default="build/bench")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    room = os.path.join(args.out, "sphere_room.json")
    write_json(room, sphere_room())
    print(room)
    path = os.path.join(args.out, "displaced_1m.json")
    stamp = path + ".params"
    key = f"displaced_1m v3 triangles={args.triangles}"
    if os.path.exists(path) and os.path.exists(stamp) and open(stamp).read() == key \
            and (not os.path.exists(PENUMBRA_BENCH) or os.path.getmtime(path) > os.path.getmtime(PENUMBRA_BENCH)):
        print(path)
        return
    tmp = path + ".tmp"
    scene = displaced_1m(args.triangles, tmp)
    with open(tmp, "w") as f:
        json.dump(scene, f, separators=(",", ":"))
    os.replace(tmp, path)
    with open(stamp, "w") as f:
        f.write(key)
    print(path)


if __name__ == "__main__":
    main()
