#!/usr/bin/env python3
"""docs/figures/many_lights.png: the many-lights scene (4000 point and 400 sphere lights over a
floor, tools/scenes/make_many_lights.py) at about the same render time per configuration,
tiled with labels (configuration, spp, render seconds, relMSE against the reference) beside
the reference (bvh at --reference-spp, another seed).

  tools/figures/many_lights_figure.py [--configs uniform,power,bvh,bvh+ris,mitsuba] [--seconds 1.0]
      [--size 192 144] [--reference-spp 8192] [--columns 3] [--mitsuba-venv build/venv-mitsuba]
      [--work build/figures/many-lights] [-o docs/figures/many_lights.png]

Configurations as tools/bench/bench-many-lights names them (penumbra_tools/many_lights_runs.py;
"mitsuba" needs the venv that tools/mitsuba/mitsuba-venv makes). Equal time: each
configuration renders at 16 spp, then at the spp that a line through its last two renders (a
fixed cost plus a cost per sample) says fills --seconds, until one is within 15% of it (at most
five renders); the tile is the last render, and its label shows the render time it took. relMSE is `penumbra compare`'s, mean (a-b)^2/(b^2+1e-2).
Prints a markdown table of the tiles for docs/figures/README.md. Standard library only.
"""
import argparse
import os
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))  # this file is tools/figures/
sys.path.insert(0, os.path.join(ROOT, "tools"))
from penumbra_tools.bitmap_font import HEIGHT, draw_text, text_width  # noqa: E402
from penumbra_tools.many_lights_runs import Runner, relmse  # noqa: E402
from penumbra_tools.png_rgb8 import read_png, write_png  # noqa: E402

GAP = 4  # background pixels between tiles and around the figure
BACKGROUND, INK = (48, 48, 48), (235, 235, 235)
NAME_SCALE = 2  # the configuration's name at twice the font's size, the numbers below it at 1x
LABEL_HEIGHT = GAP + HEIGHT * NAME_SCALE + GAP + HEIGHT + GAP


def equal_time_spp(render, seconds, multiple=1, tolerance=0.15, tries=5):
    """(spp, seconds) of the last of a few renders aiming at `seconds`: 16 spp first, then the
    spp that a line through the last two renders (a fixed cost plus a cost per sample) says, or
    a proportional step while there is one render or the line is useless; until a render is
    within `tolerance` of the target. spp stays a positive multiple of `multiple`."""
    def snap(spp):
        return max(multiple, int(round(spp / multiple)) * multiple)

    points = [(16, render(16))]
    while abs(points[-1][1] / seconds - 1) > tolerance and len(points) < tries:
        (s0, t0), (s1, t1) = points[-2] if len(points) > 1 else (0, 0.0), points[-1]
        per_sample = (t1 - t0) / (s1 - s0) if s1 != s0 else 0
        fixed = t1 - per_sample * s1
        spp = snap((seconds - fixed) / per_sample) if per_sample > 0 and 0 <= fixed < seconds else \
            snap(s1 * seconds / t1)
        if spp == s1:
            break
        points.append((spp, render(spp)))
    return points[-1]


def label_lines(config, spp, seconds, error):
    return config, f"{spp} spp  {seconds:.2f} s  relMSE {error:.3g}"


def compose(tiles, columns, out):
    """tiles: [(png path, name, detail line)], all of one size, into one figure: a grid of
    `columns`, each tile under its label strip."""
    images = [read_png(path) for path, _, _ in tiles]
    w, h = images[0][0], images[0][1]
    if any((iw, ih) != (w, h) for iw, ih, _ in images):
        raise ValueError("tiles of different sizes")
    rows = (len(tiles) + columns - 1) // columns
    width = GAP + columns * (w + GAP)
    height = GAP + rows * (LABEL_HEIGHT + h + GAP)
    pixels = bytearray(bytes(BACKGROUND) * (width * height))
    for k, ((_, name, detail), (_, _, rgb)) in enumerate(zip(tiles, images)):
        x0 = GAP + (k % columns) * (w + GAP)
        y0 = GAP + (k // columns) * (LABEL_HEIGHT + h + GAP)
        draw_text(pixels, width, x0, y0 + GAP, name, INK, NAME_SCALE, right=x0 + w)
        draw_text(pixels, width, x0, y0 + 2 * GAP + HEIGHT * NAME_SCALE, detail, INK, right=x0 + w)
        if text_width(detail) > w or text_width(name, NAME_SCALE) > w:
            print(f"many_lights_figure: the label {name!r} / {detail!r} is wider than its tile", file=sys.stderr)
        top = y0 + LABEL_HEIGHT
        for y in range(h):
            start = 3 * ((top + y) * width + x0)
            pixels[start:start + 3 * w] = rgb[3 * y * w:3 * (y + 1) * w]
    write_png(out, width, height, pixels)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--configs", default="uniform,power,bvh,bvh+ris,mitsuba")
    ap.add_argument("--seconds", type=float, default=1.0, help="render seconds per configuration")
    ap.add_argument("--size", type=int, nargs=2, default=[192, 144], metavar=("W", "H"))
    ap.add_argument("--reference-spp", type=int, default=8192)
    ap.add_argument("--columns", type=int, default=3)
    ap.add_argument("--mitsuba-venv", default=os.path.join(ROOT, "build", "venv-mitsuba"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "figures", "many-lights"))
    ap.add_argument("-o", "--out", default=os.path.join(ROOT, "docs", "figures", "many_lights.png"))
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    scene = os.path.join(a.work, "many_lights.json")
    subprocess.run([sys.executable, os.path.join(ROOT, "tools", "scenes", "make_many_lights.py"), "--size",
                    str(a.size[0]), str(a.size[1]), "--out", scene], check=True, capture_output=True)
    configs = a.configs.split(",")
    runner = Runner(scene, configs, a.mitsuba_venv)

    ref = os.path.join(a.work, "reference.exr")
    ref_seconds = runner.render(ref, a.reference_spp, "bvh", 4242, png=ref[:-4] + ".png")
    tiles, table = [], []
    for config in configs:
        exr, png = (os.path.join(a.work, f"{config}.{ext}") for ext in ("exr", "png"))
        multiple = 4 if config == "mitsuba-ld" else 1  # ldsampler renders multiples of 4 spp
        spp, seconds = equal_time_spp(lambda n: runner.render(exr, n, config, 17, png=png), a.seconds, multiple)
        error = relmse(exr, ref)
        tiles.append((png, *label_lines(config, spp, seconds, error)))
        table.append(f"| {config} | {spp} | {seconds:.2f} | {error:.3g} |")
    tiles.append((ref[:-4] + ".png", "reference", f"bvh  {a.reference_spp} spp  {ref_seconds:.1f} s"))
    compose(tiles, a.columns, a.out)
    print(f"{a.out}: {os.path.getsize(a.out)} bytes, {a.size[0]}x{a.size[1]} tiles, about {a.seconds:g} s each\n")
    print("| configuration | spp | render s | relMSE |\n|---|---|---|---|")
    print("\n".join(table))


if __name__ == "__main__":
    main()
