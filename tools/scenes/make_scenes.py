#!/usr/bin/env python3
"""Writes the direct-illumination example scenes under scenes/ (run from the repository root).

The geometry that is easier to compute than to type (the Veach & Guibas plates, which are
tilted so that each mirrors the row of lights towards the camera) lives here; the JSON files
are committed so a user can render them without Python.
"""
import json
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # tools/: penumbra_tools
from penumbra_tools.vec import add, cross, normalize, scale, sub


def r(v, digits=5):
    return [round(c, digits) for c in v]


def quad(origin, eu, ev, material=None, **extra):
    q = {"type": "quad", "origin": r(origin), "edge_u": r(eu), "edge_v": r(ev)}
    if material:
        q["material"] = material
    q.update(extra)
    return q


def box_mesh(center, size, angle_deg, material):
    """An axis-aligned box rotated about y, as a mesh with outward counter-clockwise faces."""
    cx, cy, cz = center
    sx, sy, sz = [s / 2 for s in size]
    a = math.radians(angle_deg)
    ca, sa = math.cos(a), math.sin(a)
    pts = []
    for x in (-sx, sx):
        for y in (-sy, sy):
            for z in (-sz, sz):
                pts.append([cx + ca * x + sa * z, cy + y, cz - sa * x + ca * z])
    # vertex index = 4*ix + 2*iy + iz
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    idx = []
    for f in faces:
        idx += [f[0], f[1], f[2], f[0], f[2], f[3]]
    return {"type": "mesh", "positions": [round(c, 5) for p in pts for c in p], "indices": idx, "material": material}


def cornell():
    white, red, green = "white", "red", "green"
    shapes = [
        quad([-1, 0, -1], [0, 0, 2], [2, 0, 0], white),        # floor
        quad([-1, 2, -1], [2, 0, 0], [0, 0, 2], white),        # ceiling
        quad([-1, 0, -1], [2, 0, 0], [0, 2, 0], white),        # back
        quad([-1, 0, -1], [0, 2, 0], [0, 0, 2], red),          # left
        quad([1, 0, -1], [0, 0, 2], [0, 2, 0], green),         # right
        box_mesh([0.35, 0.3, 0.35], [0.6, 0.6, 0.6], -18, white),
        box_mesh([-0.35, 0.6, -0.3], [0.6, 1.2, 0.6], 17, white),
        quad([-0.25, 1.99, -0.2], [0.5, 0, 0], [0, 0, 0.4], None, emission=[17, 12, 4]),
    ]
    return {
        "camera": {"eye": [0, 1, 3.9], "target": [0, 1, 0], "up": [0, 1, 0], "fov_y": 37},
        "film": {"width": 400, "height": 400},
        "sampler": {"spp": 64},
        "integrator": {"type": "direct", "strategy": "mis"},
        "materials": {
            "white": {"type": "diffuse", "albedo": [0.73, 0.73, 0.73]},
            "red": {"type": "diffuse", "albedo": [0.65, 0.05, 0.05]},
            "green": {"type": "diffuse", "albedo": [0.12, 0.45, 0.15]},
        },
        "shapes": shapes,
    }


def veach_mis():
    """Veach & Guibas 1995, fig. 4: four glossy plates (exponent rising towards the camera)
    lit by four sphere lights of radius 0.03 .. 0.9 and equal power."""
    eye = [0, 2, 15]
    lights_y, lights_z = 2.6, -1.6
    radii = [0.03, 0.1, 0.3, 0.9]
    xs = [-3.75, -1.25, 1.25, 3.75]
    colors = [[1.0, 0.35, 0.3], [1.0, 0.85, 0.3], [0.35, 0.9, 0.4], [0.35, 0.55, 1.0]]
    power = 60.0
    shapes = []
    for x, rad, c in zip(xs, radii, colors):
        mean = sum(c) / 3
        shapes.append({"type": "sphere", "center": [x, lights_y, lights_z], "radius": rad,
                       "power": r([power * ci / mean for ci in c], 4), "material": "black"})
    exps = [20, 100, 800, 8000]
    materials = {"black": {"type": "diffuse", "albedo": [0, 0, 0]},
                 "floor": {"type": "diffuse", "albedo": [0.3, 0.3, 0.3]}}
    light_center = [0, lights_y, lights_z]
    for i, e in enumerate(exps):
        z = 0.6 + 1.05 * i
        y = -0.25 - 0.35 * i
        center = [0, y, z]
        n = normalize(add(normalize(sub(eye, center)), normalize(sub(light_center, center))))
        ev = scale(normalize(cross([1, 0, 0], n)), 0.95)
        eu = [8, 0, 0]
        if cross(eu, ev)[1] * n[1] + cross(eu, ev)[2] * n[2] < 0:
            ev = scale(ev, -1)
        origin = sub(sub(center, scale(eu, 0.5)), scale(ev, 0.5))
        name = "plate%d" % i
        materials[name] = {"type": "phong", "kd": [0.07, 0.07, 0.07], "ks": [0.6, 0.6, 0.6], "exponent": e}
        shapes.append(quad(origin, eu, ev, name))
    shapes.append(quad([-12, -2.5, -6], [0, 0, 22], [24, 0, 0], "floor"))
    shapes.append(quad([-12, -2.5, -6], [24, 0, 0], [0, 12, 0], "floor"))
    return {
        "camera": {"eye": eye, "target": [0, 0.2, 0.8], "up": [0, 1, 0], "fov_y": 33},
        "film": {"width": 512, "height": 320},
        "sampler": {"spp": 16},
        "integrator": {"type": "direct", "strategy": "mis", "heuristic": "power", "light_selection": "power"},
        "materials": materials,
        "shapes": shapes,
        "lights": [{"type": "point", "position": [0, 8, 12], "power": [40, 40, 40]}],
    }


def mesh_light():
    # An emissive ring of triangles (a torus-like band) above a floor with two spheres.
    pos, idx = [], []
    n, R, w = 24, 0.8, 0.12
    for i in range(n):
        a = 2 * math.pi * i / n
        for rr in (R - w, R + w):
            pos += [round(rr * math.cos(a), 5), 1.6, round(rr * math.sin(a), 5)]
    for i in range(n):
        j = (i + 1) % n
        a0, a1, b0, b1 = 2 * i, 2 * i + 1, 2 * j, 2 * j + 1
        # counter-clockwise seen from below: the ring emits downwards
        idx += [a0, a1, b0, a1, b1, b0]
    return {
        "camera": {"eye": [0, 1.6, 4.2], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov_y": 40},
        "film": {"width": 480, "height": 360},
        "sampler": {"spp": 32},
        "integrator": {"type": "direct", "strategy": "mis"},
        "materials": {
            "floor": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
            "glossy": {"type": "phong", "kd": [0.3, 0.1, 0.1], "ks": [0.5, 0.5, 0.5], "exponent": 60},
            "matte": {"type": "diffuse", "albedo": [0.2, 0.4, 0.7]},
        },
        "shapes": [
            quad([-4, 0, -4], [0, 0, 8], [8, 0, 0], "floor"),
            {"type": "sphere", "center": [-0.45, 0.4, 0], "radius": 0.4, "material": "glossy"},
            {"type": "sphere", "center": [0.5, 0.3, 0.3], "radius": 0.3, "material": "matte"},
            {"type": "mesh", "positions": pos, "indices": idx, "power": [40, 36, 30], "two_sided": False},
        ],
    }


def lecture_spheres():
    """Lecture, 'Sphere Light - Validation': equal power, different radii, and a point light
    give identical irradiance profiles on the plane below (no occluders)."""
    P = 30.0
    return {
        "camera": {"eye": [0, 5.5, 5.5], "target": [0, 0, 0.3], "up": [0, 1, 0], "fov_y": 45},
        "film": {"width": 600, "height": 300},
        "sampler": {"spp": 32},
        "integrator": {"type": "direct", "strategy": "light", "sphere_sampling": "solid_angle"},
        "materials": {"plane": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
                      "black": {"type": "diffuse", "albedo": [0, 0, 0]}},
        "shapes": [
            quad([-6, 0, -3], [0, 0, 6], [12, 0, 0], "plane"),
            {"type": "sphere", "center": [-3, 1, 0], "radius": 0.5, "power": [P, P, P], "material": "black"},
            {"type": "sphere", "center": [0, 1, 0], "radius": 0.1, "power": [P, P, P], "material": "black"},
        ],
        "lights": [{"type": "point", "position": [3, 1, 0], "power": [P, P, P]}],
    }


def pbr_lights():
    """A GGX metal (glTF metallic-roughness, roughness 0.2) under a small and a large sphere
    light of equal power: light sampling wins on the small light's highlight, BRDF sampling
    on the large one's, MIS on both (the figure pbr_strategies.png)."""
    P = 40.0
    return {
        "camera": {"eye": [0, 2, 6], "target": [0, 0, 0.3], "up": [0, 1, 0], "fov_y": 40},
        "film": {"width": 480, "height": 320},
        "sampler": {"spp": 16},
        "integrator": {"type": "direct", "strategy": "mis"},
        "materials": {"metal": {"type": "pbr", "base_color": [0.95, 0.8, 0.6], "metallic": 1, "roughness": 0.2},
                      "black": {"type": "diffuse", "albedo": [0, 0, 0]}},
        "shapes": [
            quad([-5, 0, -4], [0, 0, 8], [10, 0, 0], "metal"),
            {"type": "sphere", "center": [-1.8, 1.2, -1.5], "radius": 0.05, "power": [P, P, P], "material": "black"},
            {"type": "sphere", "center": [1.8, 1.2, -1.5], "radius": 0.7, "power": [P, P, P], "material": "black"},
        ],
        "lights": [],
    }


def main():
    os.makedirs("scenes", exist_ok=True)
    for name, scene in [("cornell", cornell()), ("veach_mis", veach_mis()), ("mesh_light", mesh_light()),
                        ("lecture_spheres", lecture_spheres()), ("pbr_lights", pbr_lights())]:
        text = json.dumps(scene, indent=2)
        # Keep arrays of numbers on one line: positions and colours read better that way.
        text = re.sub(r"\[[-0-9.,\se]*\]", lambda m: re.sub(r"\s+", " ", m.group(0)).replace("[ ", "[").replace(" ]", "]"), text)
        with open(os.path.join("scenes", name + ".json"), "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
