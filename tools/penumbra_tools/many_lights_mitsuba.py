"""Mitsuba 3 as one configuration of tools/bench/bench-many-lights: a long-lived process that
loads the scene once and then renders on request, so that the bench times only mi.render and
the evaluation of its image (dr.eval + dr.sync_thread), not Python's import, the scene load or
(after the first render) Dr.Jit's kernel compilation.

  python many_lights_mitsuba.py SCENE.json [SAMPLER]   (Mitsuba's venv; DRJIT_LIBLLVM_PATH set)

SAMPLER is Mitsuba's sampler plugin: `independent` (its default) or `ldsampler` (its
low-discrepancy sampler, the counterpart of Penumbra's default Owen-scrambled Sobol'; it
wants a sample count that is a power of four, so a render is split into passes of powers of
four, each an independent scrambling, which keeps the estimate unbiased).

Protocol, one line each way: stdin "SPP SEED OUT.exr [OUT.png]", stdout "SECONDS" (paths without
spaces; OUT.png, when given, is the image as `penumbra render --png` writes it: 8-bit sRGB of the
clamped radiance). The scene goes through
the translator (penumbra_tools/mitsuba_penumbra.py) with its integrator forced to the estimator
of Penumbra's mis 1/1: Mitsuba's `direct` with emitter_samples=1, bsdf_samples=1, emitters
selected uniformly (Mitsuba's own rule; the translator adds no power weights under "uniform").
"""
import json
import math
import os
import sys
import time

PASS_SAMPLES = 1 << 22

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # tools/


def pass_samples(left, per_pass, power_of_four):
    """Samples per pixel of the next pass: at most per_pass (at least 1) and what is left. When
    the sampler needs a power of four (ldsampler rounds other counts up), the largest one of at
    least 4: `left` must then be a multiple of 4, and stays one."""
    n = max(1, min(per_pass, left))
    if power_of_four:
        n = max(4, 4 ** int(math.log(n, 4) + 1e-9))
    return n


def main():
    import numpy as np
    import drjit as dr
    import mitsuba as mi
    mi.set_variant(os.environ.get("MITSUBA_VARIANT", "llvm_ad_rgb"))
    mi.set_log_level(mi.LogLevel.Error)  # Mitsuba logs to stdout, which carries the protocol
    from penumbra_tools import mitsuba_penumbra as mp
    from penumbra_tools.mitsuba_compare.images import write_exr

    path = sys.argv[1]
    sampler = sys.argv[2] if len(sys.argv) > 2 else "independent"
    with open(path) as f:
        scene_json = json.load(f)
    scene_json["integrator"] = {"type": "direct", "strategy": "mis", "light_samples": 1, "bsdf_samples": 1,
                                "light_selection": "uniform"}
    scene = mi.load_dict(mp.translate(scene_json, sampler=sampler, base_dir=os.path.dirname(os.path.abspath(path))))
    mi.render(scene, spp=pass_samples(1, 1, sampler == "ldsampler"))  # compiles the kernels once; later renders reuse them
    film = scene_json.get("film", {})
    pixels = int(film.get("width", 512)) * int(film.get("height", 512))
    # Mitsuba's llvm wavefront holds every sample of a render at once: passes of at most
    # PASS_SAMPLES samples in all keep its memory bounded at high spp.
    per_pass = max(1, PASS_SAMPLES // pixels)
    for line in sys.stdin:
        spp, seed, out, *png = line.split()
        spp, seed = int(spp), int(seed)
        if sampler == "ldsampler" and spp % 4:
            sys.exit(f"many_lights_mitsuba.py: ldsampler renders multiples of 4 spp, not {spp}")
        t0 = time.perf_counter()
        acc, done, k = None, 0, 0
        while done < spp:
            n = pass_samples(spp - done, per_pass, sampler == "ldsampler")
            img = mi.render(scene, spp=n, seed=(seed * 100003 + k) & 0xFFFFFFFF)  # Mitsuba takes a 32-bit seed
            acc = img * n if acc is None else acc + img * n
            dr.eval(acc)
            done, k = done + n, k + 1
        dr.sync_thread()
        seconds = time.perf_counter() - t0
        img = np.array(acc, dtype=np.float32)[:, :, :3] / spp
        write_exr(out, img)
        if png:
            mi.Bitmap(img).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True).write(png[0])
        print(f"{seconds:.6f}", flush=True)


if __name__ == "__main__":
    main()
