#!/usr/bin/env python3
"""docs/figures/denoise.png: the Cornell box at 4 spp, noisy | denoised | 1024-spp reference.

Run with a Python that has the module and pyoidn (tools/setup makes build/venv-denoise):
    PYTHONPATH=build/python build/venv-denoise/bin/python tools/figures/denoise_figure.py
It prints each panel's relMSE against the reference (docs/figures/README.md's definition)
and the seconds each step took, for the caption in docs/guide/python.md.
"""
import pathlib
import sys
import time

import numpy as np

import penumbra

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE = ROOT / "scenes" / "cornell.json"
GAP = 4  # white pixels between panels


def relmse(a, b):
    return float(np.mean((a - b) ** 2 / (b * b + 1e-2)))


def main(out):
    start = time.perf_counter()
    noisy = penumbra.render(SCENE, spp=4, seed=1, aovs=["albedo", "normal"])
    noisy_seconds = time.perf_counter() - start
    start = time.perf_counter()
    denoised = penumbra.denoise(noisy["rgb"], albedo=noisy["albedo"], normal=noisy["normal"])
    denoise_seconds = time.perf_counter() - start
    start = time.perf_counter()
    reference = penumbra.render(SCENE, spp=1024, seed=2)["rgb"]  # another seed: independent error
    reference_seconds = time.perf_counter() - start
    print(f"noisy 4 spp: relMSE {relmse(noisy['rgb'], reference):.5f} ({noisy_seconds:.2f} s with the AOVs)")
    print(f"denoised (albedo + normal): relMSE {relmse(denoised, reference):.5f} (+{denoise_seconds:.2f} s)")
    print(f"reference 1024 spp ({reference_seconds:.1f} s)")
    h = reference.shape[0]
    gap = np.ones((h, GAP, 3), np.float32)
    strip = np.concatenate([noisy["rgb"], gap, denoised, gap, reference], axis=1)
    penumbra.write_png(out, {"rgb": np.ascontiguousarray(strip)})


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "docs" / "figures" / "denoise.png"))
