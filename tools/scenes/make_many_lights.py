#!/usr/bin/env python3
"""Writes a many-lights benchmark scene (issue #47): `points` point lights and `spheres` small
sphere lights scattered over a diffuse floor, their powers spanning four decades (log-uniform
over 10^0 .. 10^4 times a base), seen at a slant. Direct integrator, MIS with its defaults;
`light_selection` is left to the caller (--set integrator.light_selection=...).

Usage: tools/scenes/make_many_lights.py [--points N] [--spheres M] [--size W H] [--seed S] [--out FILE]
Standard library only; the same arguments give the same file.
"""
import argparse
import json
import os
import random


def scene(points, spheres, width, height, seed):
    rng = random.Random(seed)
    half = 20.0  # the floor and the lights cover [-half, half]^2
    lights = []
    for _ in range(points):
        power = 0.002 * 10 ** (4 * rng.random())
        lights.append({"type": "point",
                       "position": [rng.uniform(-half, half), rng.uniform(0.5, 2.5), rng.uniform(-half, half)],
                       "power": [power, power, power]})
    shapes = [{"type": "quad", "origin": [-2 * half, 0, -2 * half], "edge_u": [0, 0, 4 * half],
               "edge_v": [4 * half, 0, 0], "material": "floor"}]
    for _ in range(spheres):
        power = 0.002 * 10 ** (4 * rng.random())
        c = [rng.uniform(-half, half), rng.uniform(0.6, 3.0), rng.uniform(-half, half)]
        shapes.append({"type": "sphere", "center": c, "radius": rng.uniform(0.05, 0.2),
                       "power": [power, 0.8 * power, 0.6 * power], "material": "black"})
    return {
        "camera": {"eye": [0, 9, 24], "target": [0, 0, 2], "up": [0, 1, 0], "fov_y": 55},
        "film": {"width": width, "height": height},
        "sampler": {"spp": 16, "seed": 1},
        "integrator": {"type": "direct", "strategy": "mis"},
        "materials": {"floor": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
                      "black": {"type": "diffuse", "albedo": [0, 0, 0]}},
        "shapes": shapes,
        "lights": lights,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=4000)
    ap.add_argument("--spheres", type=int, default=400)
    ap.add_argument("--size", type=int, nargs=2, default=[96, 72], metavar=("W", "H"))
    ap.add_argument("--seed", type=int, default=47)
    ap.add_argument("--out", default=os.path.join("build", "bench", "many_lights.json"))
    a = ap.parse_args()
    os.makedirs(os.path.dirname(a.out) or ".", exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(scene(a.points, a.spheres, a.size[0], a.size[1], a.seed), f)
    print(a.out)


if __name__ == "__main__":
    main()
