#!/usr/bin/env python3
"""Writes a many-lights benchmark scene, one of three kinds (--kind):

  points  `points` point lights and `spheres` small sphere lights scattered over a diffuse
          floor, their powers spanning four decades (log-uniform over 10^0 .. 10^4 times a
          base), seen at a slant.
  mesh    one mesh light of 2 x `grid`^2 emissive triangles (100,352 by default): a wavy
          canopy 4 +- 0.5 above the floor, facing down, over a dozen grey spheres that shade
          the floor, seen from under the canopy. The mesh is a binary PLY file written beside
          the scene (`mesh` shape with `file`); one emission for all its triangles. (Small
          tiles scattered in the air, seen from above, made a worse benchmark: their sub-pixel
          backs' aliasing, common to every light selection, was most of the error.)
  quads   a closed room (floor, walls, ceiling) lit by a ceiling grid of `panels` x `panels`
          small quad lights facing down, their powers over two decades, with a few pillars;
          the camera is inside.

Direct integrator, MIS with its defaults; `light_selection` is left to the caller
(--set integrator.light_selection=...).

Usage: tools/scenes/make_many_lights.py [--kind points|mesh|quads] [--points N] [--spheres M]
       [--grid G] [--panels P] [--size W H] [--seed S] [--out FILE]
Standard library only; the same arguments give the same files.
"""
import argparse
import json
import math
import os
import random
import struct

HALF = 20.0  # the points and mesh scenes' lights cover [-HALF, HALF]^2 over the floor


def _base(width, height, camera):
    return {
        "camera": camera,
        "film": {"width": width, "height": height},
        "sampler": {"spp": 16, "seed": 1},
        "integrator": {"type": "direct", "strategy": "mis"},
        "materials": {"floor": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
                      "black": {"type": "diffuse", "albedo": [0, 0, 0]},
                      "grey": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
        "shapes": [],
        "lights": [],
    }


def _floor():
    """The floor quad, front face up: edge_u x edge_v = +y."""
    return {"type": "quad", "origin": [-2 * HALF, 0, -2 * HALF], "edge_u": [0, 0, 4 * HALF],
            "edge_v": [4 * HALF, 0, 0], "material": "floor"}


SLANT_CAMERA = {"eye": [0, 9, 24], "target": [0, 0, 2], "up": [0, 1, 0], "fov_y": 55}


def points_scene(points, spheres, width, height, seed):
    rng = random.Random(seed)
    s = _base(width, height, SLANT_CAMERA)
    del s["materials"]["grey"]
    for _ in range(points):
        power = 0.002 * 10 ** (4 * rng.random())
        s["lights"].append({"type": "point",
                            "position": [rng.uniform(-HALF, HALF), rng.uniform(0.5, 2.5), rng.uniform(-HALF, HALF)],
                            "power": [power, power, power]})
    s["shapes"].append(_floor())
    for _ in range(spheres):
        power = 0.002 * 10 ** (4 * rng.random())
        c = [rng.uniform(-HALF, HALF), rng.uniform(0.6, 3.0), rng.uniform(-HALF, HALF)]
        s["shapes"].append({"type": "sphere", "center": c, "radius": rng.uniform(0.05, 0.2),
                            "power": [power, 0.8 * power, 0.6 * power], "material": "black"})
    return s


def _rotate(p, axis_angle_x, axis_angle_z):
    """p rotated about x, then about z (radians)."""
    x, y, z = p
    c, s = math.cos(axis_angle_x), math.sin(axis_angle_x)
    y, z = c * y - s * z, s * y + c * z
    c, s = math.cos(axis_angle_z), math.sin(axis_angle_z)
    return [c * x - s * y, s * x + c * y, z]


def canopy_mesh(grid):
    """(positions, triangles) of a wavy canopy over the floor: grid x grid squares over
    [-HALF, HALF]^2 at heights 4 +- 0.5, two triangles each, facing down (front face =
    counter-clockwise seen from below)."""
    pos = []
    for i in range(grid + 1):
        for j in range(grid + 1):
            x, z = -HALF + 2 * HALF * i / grid, -HALF + 2 * HALF * j / grid
            pos.append([x, 4.0 + 0.5 * math.sin(x / 3) * math.cos(z / 3), z])
    tris = []
    for i in range(grid):
        for j in range(grid):
            a, b = i * (grid + 1) + j, (i + 1) * (grid + 1) + j  # b is a's neighbour in +x
            # (b - a) x (c - a) with b = a + x, c = a + x + z: -y, facing down.
            tris += [(a, b, b + 1), (a, b + 1, a + 1)]
    return pos, tris


def write_ply(path, pos, tris):
    """Binary little-endian PLY: float x y z per vertex, uchar-counted int vertex_indices per face."""
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {len(pos)}\nproperty float x\nproperty float y\nproperty float z\n"
              f"element face {len(tris)}\nproperty list uchar int vertex_indices\nend_header\n")
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(b"".join(struct.pack("<3f", *p) for p in pos))
        f.write(b"".join(struct.pack("<B3i", 3, *t) for t in tris))


def mesh_scene(grid, width, height, seed, ply_name):
    """The scene; the mesh is written by main() as ply_name beside the scene file."""
    rng = random.Random(seed)
    s = _base(width, height, {"eye": [0, 2.5, 22], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov_y": 55})
    del s["materials"]["black"]
    s["shapes"].append(_floor())
    for _ in range(12):
        r = rng.uniform(1.0, 2.5)
        s["shapes"].append({"type": "sphere", "center": [rng.uniform(-HALF, HALF), r, rng.uniform(-HALF, 0.6 * HALF)],
                            "radius": r, "material": "grey"})
    # About 6 kW over ~1600 m^2: radiance ~1.2, the floor's about 0.7 where it sees the whole canopy.
    s["shapes"].append({"type": "mesh", "file": ply_name, "power": [6000, 5000, 4000], "material": "grey"})
    return s, canopy_mesh(grid)


def quads_scene(panels, width, height, seed):
    rng = random.Random(seed)
    w, h = 10.0, 3.0  # the room is [-w, w] x [0, h] x [-w, w]
    s = _base(width, height, {"eye": [-8.5, 1.6, 8.5], "target": [3, 0.9, -3], "up": [0, 1, 0], "fov_y": 60})
    del s["materials"]["black"]
    s["materials"]["wall"] = {"type": "diffuse", "albedo": [0.7, 0.65, 0.6]}

    def quad(origin, u, v, material="wall", **extra):
        return {"type": "quad", "origin": origin, "edge_u": u, "edge_v": v, "material": material, **extra}

    s["shapes"] += [
        quad([-w, 0, -w], [0, 0, 2 * w], [2 * w, 0, 0], "floor"),  # normal +y
        quad([-w, h, -w], [2 * w, 0, 0], [0, 0, 2 * w]),  # ceiling, normal -y
        quad([-w, 0, -w], [2 * w, 0, 0], [0, h, 0]),  # back wall z = -w, normal +z
        quad([-w, 0, w], [0, h, 0], [2 * w, 0, 0]),  # front wall z = w, normal -z
        quad([-w, 0, -w], [0, h, 0], [0, 0, 2 * w]),  # left wall x = -w, normal +x
        quad([w, 0, -w], [0, 0, 2 * w], [0, h, 0]),  # right wall x = w, normal -x
    ]
    for _ in range(6):  # pillars: four sides each, outward
        x, z, r = rng.uniform(-0.7 * w, 0.7 * w), rng.uniform(-0.7 * w, 0.7 * w), rng.uniform(0.2, 0.5)
        s["shapes"] += [quad([x - r, 0, z - r], [0, h, 0], [2 * r, 0, 0], "grey"),
                        quad([x + r, 0, z + r], [0, h, 0], [-2 * r, 0, 0], "grey"),
                        quad([x - r, 0, z + r], [0, h, 0], [0, 0, -2 * r], "grey"),
                        quad([x + r, 0, z - r], [0, h, 0], [0, 0, 2 * r], "grey")]
    step, side = 2 * w / panels, 0.3 * 2 * w / panels
    for i in range(panels):
        for j in range(panels):
            power = 0.05 * 10 ** (2 * rng.random())
            x0, z0 = -w + (i + 0.5) * step - side / 2, -w + (j + 0.5) * step - side / 2
            # edge_u x edge_v = (side, 0, 0) x (0, 0, side) = -y: the panel faces down.
            s["shapes"].append(quad([x0, h - 0.02, z0], [side, 0, 0], [0, 0, side], "grey",
                                    power=[power, 0.95 * power, 0.85 * power]))
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kind", choices=["points", "mesh", "quads"], default="points")
    ap.add_argument("--points", type=int, default=4000)
    ap.add_argument("--spheres", type=int, default=400)
    ap.add_argument("--grid", type=int, default=224, help="mesh: a canopy of grid x grid squares, two triangles each")
    ap.add_argument("--panels", type=int, default=20, help="quads: a ceiling grid of panels x panels")
    ap.add_argument("--size", type=int, nargs=2, default=[96, 72], metavar=("W", "H"))
    ap.add_argument("--seed", type=int, default=47)
    ap.add_argument("--out", default=os.path.join("build", "bench", "many_lights.json"))
    a = ap.parse_args()
    os.makedirs(os.path.dirname(a.out) or ".", exist_ok=True)
    if a.kind == "points":
        s = points_scene(a.points, a.spheres, a.size[0], a.size[1], a.seed)
    elif a.kind == "mesh":
        ply = os.path.splitext(os.path.basename(a.out))[0] + ".ply"
        s, (pos, tris) = mesh_scene(a.grid, a.size[0], a.size[1], a.seed, ply)
        write_ply(os.path.join(os.path.dirname(a.out) or ".", ply), pos, tris)
    else:
        s = quads_scene(a.panels, a.size[0], a.size[1], a.seed)
    with open(a.out, "w") as f:
        json.dump(s, f)
    print(a.out)


if __name__ == "__main__":
    main()
