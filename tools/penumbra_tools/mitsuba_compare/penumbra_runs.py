"""Penumbra's side of the comparison, through build/penumbra and build/penumbra_bench:
timed renders (render time from the EXR header), rays per sample, a cached high-spp
reference, and renders at rising spp until an error target (time-to-error)."""
import os
import statistics
import subprocess
import time

from penumbra_tools.mitsuba_compare.images import read_exr, relmse
from penumbra_tools.mitsuba_compare.paths import PENUMBRA, PENUMBRA_BENCH, WORK


def penumbra_render(scene_path, out, spp=None, seed=None, width=None, height=None, sampler=None):
    """Renders into out; returns (image, render seconds from the header, wall seconds)."""
    cmd = [PENUMBRA, "render", scene_path, "-o", out, "--quiet"]
    if sampler is not None:
        cmd += ["--set", f"sampler.type={sampler}"]
    if spp is not None:
        cmd += ["--spp", str(spp)]
    if seed is not None:
        cmd += ["--seed", str(seed)]
    if width:
        cmd += ["--width", str(width), "--height", str(height)]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}): {p.stderr.strip()}")
    img, meta = read_exr(out)
    return img, float(meta["penumbra:render_seconds"]), wall


def penumbra_rays_per_sample(scene_path):
    """Rays (camera, shadow, BRDF) per pixel sample, counted by penumbra_bench --count-rays."""
    p = subprocess.run([PENUMBRA_BENCH, "--count-rays", scene_path], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"penumbra_bench --count-rays {scene_path} failed ({p.returncode}): {p.stderr.strip()}")
    return float(p.stdout.split()[-1])


def penumbra_reference(scene_path, name, spp, width, height, seed=4242):
    """High-spp Penumbra image and its path, cached in build/mitsuba-compare by its parameters."""
    out = os.path.join(WORK, f"{name}_ref_{width}x{height}_{spp}spp_s{seed}.exr")
    if os.path.exists(out) and os.path.getmtime(out) > os.path.getmtime(scene_path) \
            and os.path.getmtime(out) > os.path.getmtime(PENUMBRA):
        return read_exr(out)[0], out
    img, _, _ = penumbra_render(scene_path, out, spp=spp, seed=seed, width=width, height=height)
    return img, out


def penumbra_tte(scene_path, name, ref, target, max_spp, width, height, sampler=None, runs=1):
    """[spp, render seconds, relMSE] at 1, 2, 4, ... spp until relMSE < target or max_spp; the
    seconds are the median of `runs` renders of the same image (same seed, so the same relMSE):
    one render of a few hundredths of a second can take half as long again on a shared machine."""
    points = []
    spp = 1
    while spp <= max_spp:
        out = os.path.join(WORK, f"{name}_tte_penumbra.exr")
        times = []
        for _ in range(max(1, runs)):
            img, t, _ = penumbra_render(scene_path, out, spp=spp, seed=17 + spp, width=width, height=height,
                                        sampler=sampler)
            times.append(t)
        e = relmse(img, ref)
        points.append([spp, statistics.median(times), e])
        if e < target:
            break
        spp *= 2
    return points
