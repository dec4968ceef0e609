#!/usr/bin/python3
"""A small dataset from one process: a camera orbit of a glTF model, one EXR a frame (rgb,
depth, normal, shape_id, material_id) and a preview grid PNG (docs/guide/python.md).

One penumbra.Renderer keeps the device, the uploaded model and the compiled kernel; each
frame only moves the camera (no recompilation, no re-upload), so the frames cost their
samples and little else. The grid shows a few frames, a row each: rgb, then each layer as
the preview shows it (penumbra.false_color: depth near-bright, normals n * 0.5 + 0.5, ids
as hashed colours).

    examples/dataset.py [--scene scenes/gltf_model.json] [--frames 24] [--size 160 120]
                        [--spp 16] [--out dataset]
"""
import argparse
import json
import math
import pathlib
import sys
import time

import numpy as np

import penumbra


def orbit(camera, frames):
    """Eye positions on a horizontal circle around the camera's target, through its eye."""
    eye, target = camera["eye"], camera["target"]
    radius = math.hypot(eye[0] - target[0], eye[2] - target[2])
    start = math.atan2(eye[0] - target[0], eye[2] - target[2])
    return [[target[0] + radius * math.sin(start + 2 * math.pi * i / frames), eye[1],
             target[2] + radius * math.cos(start + 2 * math.pi * i / frames)] for i in range(frames)]


LAYERS = ["depth", "normal", "shape_id", "material_id"]


def grid(images, columns):
    """The images (all of one shape) tiled row by row; blank tiles fill the last row."""
    rows = -(-len(images) // columns)
    h, w, c = images[0].shape
    out = np.zeros((rows * h, columns * w, c), np.float32)
    for i, image in enumerate(images):
        r, k = divmod(i, columns)
        out[r * h:(r + 1) * h, k * w:(k + 1) * w] = image
    return out


def main():
    root = pathlib.Path(__file__).resolve().parents[1]
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default=str(root / "scenes" / "gltf_model.json"))
    parser.add_argument("--frames", type=int, default=24)
    parser.add_argument("--size", type=int, nargs=2, default=[160, 120], metavar=("WIDTH", "HEIGHT"))
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--out", default="dataset", help="folder for frame_NNN.exr and preview.png")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    camera = json.loads(pathlib.Path(args.scene).read_text())["camera"]
    start = time.monotonic()
    renderer = penumbra.Renderer(args.scene, width=args.size[0], height=args.size[1], spp=args.spp, seed=0,
                                 aovs=LAYERS)
    setup_seconds = time.monotonic() - start
    rows = min(4, args.frames)  # frames shown in the grid, spread over the orbit
    shown = {round(k * (args.frames - 1) / max(rows - 1, 1)) for k in range(rows)}
    tiles = []
    start = time.monotonic()
    for i, eye in enumerate(orbit(camera, args.frames)):
        frame = renderer.render(set={"camera.eye": eye})
        penumbra.write_exr(out / f"frame_{i:03d}.exr", frame)
        if i in shown:
            tiles += [frame["rgb"]] + [penumbra.false_color(frame, name) for name in LAYERS]
    seconds = time.monotonic() - start
    penumbra.write_png(out / "preview.png", {"rgb": grid(tiles, columns=1 + len(LAYERS))})

    samples = args.frames * args.size[0] * args.size[1] * args.spp
    print(f"{args.frames} frames of {args.size[0]}x{args.size[1]} at {args.spp} spp in {seconds:.2f} s "
          f"({args.frames / seconds:.1f} frames/s, {samples / seconds * 1e-6:.1f} Msamples/s; "
          f"set-up {setup_seconds:.2f} s, {renderer.kernel_compilations} kernel compilations, "
          f"{renderer.scene_uploads} scene uploads) on {renderer.device}; wrote {out}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
