"""Mitsuba 3 as one configuration of tools/bench/bench-many-lights: a long-lived process that
loads the scene once and then renders on request, so that the bench times only mi.render and
the evaluation of its image (dr.eval + dr.sync_thread), not Python's import, the scene load or
(after the first render) Dr.Jit's kernel compilation.

  python many_lights_mitsuba.py SCENE.json      (Mitsuba's venv; DRJIT_LIBLLVM_PATH set)

Protocol, one line each way: stdin "SPP SEED OUT.exr", stdout "SECONDS". The scene goes through
the translator (penumbra_tools/mitsuba_penumbra.py) with its integrator forced to the estimator
of Penumbra's mis 1/1: Mitsuba's `direct` with emitter_samples=1, bsdf_samples=1, emitters
selected uniformly (Mitsuba's own rule; the translator adds no power weights under "uniform").
"""
import json
import os
import sys
import time

PASS_SAMPLES = 1 << 22

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # tools/


def main():
    import numpy as np
    import drjit as dr
    import mitsuba as mi
    mi.set_variant(os.environ.get("MITSUBA_VARIANT", "llvm_ad_rgb"))
    from penumbra_tools import mitsuba_penumbra as mp
    from penumbra_tools.mitsuba_compare.images import write_exr

    path = sys.argv[1]
    with open(path) as f:
        scene_json = json.load(f)
    scene_json["integrator"] = {"type": "direct", "strategy": "mis", "light_samples": 1, "bsdf_samples": 1,
                                "light_selection": "uniform"}
    scene = mi.load_dict(mp.translate(scene_json, base_dir=os.path.dirname(os.path.abspath(path))))
    mi.render(scene, spp=1)  # compiles the kernels once; later renders reuse them
    film = scene_json.get("film", {})
    pixels = int(film.get("width", 512)) * int(film.get("height", 512))
    # Mitsuba's llvm wavefront holds every sample of a render at once: passes of at most
    # PASS_SAMPLES samples in all keep its memory bounded at high spp.
    per_pass = max(1, PASS_SAMPLES // pixels)
    for line in sys.stdin:
        spp, seed, out = line.split(maxsplit=2)
        spp, seed = int(spp), int(seed)
        t0 = time.perf_counter()
        acc, done, k = None, 0, 0
        while done < spp:
            n = min(per_pass, spp - done)
            img = mi.render(scene, spp=n, seed=(seed * 100003 + k) & 0xFFFFFFFF)  # Mitsuba takes a 32-bit seed
            acc = img * n if acc is None else acc + img * n
            dr.eval(acc)
            done, k = done + n, k + 1
        dr.sync_thread()
        seconds = time.perf_counter() - t0
        write_exr(out.strip(), np.array(acc, dtype=np.float32) / spp)
        print(f"{seconds:.6f}", flush=True)


if __name__ == "__main__":
    main()
