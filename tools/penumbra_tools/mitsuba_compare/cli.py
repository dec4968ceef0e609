"""The comparison's command line and its plan per scene: Penumbra and Mitsuba timings (or
those of the previous run), then agreement and time-to-error at a reduced film size.
Writes results.json into build/mitsuba-compare after every scene, the report to stdout
and into docs/PERFORMANCE.md."""
import argparse
import importlib
import json
import os
import statistics
import subprocess
import sys
import time

from penumbra_tools.mitsuba_compare import agreement as agree
from penumbra_tools.mitsuba_compare.images import read_exr
from penumbra_tools.mitsuba_compare.mitsuba_worker import run_worker, worker
from penumbra_tools.mitsuba_compare.paths import DOC, INSTALL_HINT, PENUMBRA, ROOT, TOOLS, WORK, log
from penumbra_tools.mitsuba_compare.penumbra_runs import (penumbra_rays_per_sample, penumbra_reference,
                                                          penumbra_render, penumbra_tte)
from penumbra_tools.mitsuba_compare.report import machine_info, report, write_doc
from penumbra_tools.mitsuba_compare.scenes import film_size, load_scene, scene_spp, uses_python_plugins

DEFAULT_SCENES = ["scenes/cornell.json", "scenes/veach_mis.json", "build/bench/displaced_1m.json",
                  "build/bench/sphere_room.json"]
TTE_SCENES = ("cornell", "veach_mis")


def need_imports():
    try:
        for name in ("numpy", "mitsuba"):
            importlib.import_module(name)
    except ImportError as e:
        sys.exit(f"mitsuba_compare: {e}; {INSTALL_HINT}")


def main(description):
    ap = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--scenes", nargs="+", default=None)
    ap.add_argument("--runs", type=int, default=5, help="timed renders per renderer (median)")
    ap.add_argument("--scalar-runs", type=int, default=2, help="timed scalar_rgb renders")
    ap.add_argument("--scalar-max-seconds", type=float, default=20,
                    help="lower scalar_rgb's spp so one render takes about this long")
    ap.add_argument("--quality-scale", type=float, default=0.5, help="film scale for agreement and time-to-error")
    ap.add_argument("--ref-spp", type=int, default=512)
    ap.add_argument("--target", type=float, default=0.002, help="relMSE target of the time-to-error runs")
    ap.add_argument("--max-spp", type=int, default=256, help="time-to-error stops here")
    ap.add_argument("--tte-runs", type=int, default=3,
                    help="renders of the same image per time-to-error level (their median time counts)")
    ap.add_argument("--skip-scalar", action="store_true")
    ap.add_argument("--skip-quality", action="store_true", help="no agreement or time-to-error")
    ap.add_argument("--quick", action="store_true", help="smoke test: 1 run, 64 spp reference, 0.25 scale")
    ap.add_argument("--reuse-timings", action="store_true",
                    help="take throughput and start-up from the last run's build/mitsuba-compare/results.json")
    ap.add_argument("--no-doc", action="store_true", help="do not update docs/PERFORMANCE.md")
    args = ap.parse_args()
    if args.worker:
        worker(json.loads(args.worker))
        return
    args.argv = sys.argv[1:]
    need_imports()
    if args.quick:
        args.runs, args.scalar_runs, args.ref_spp, args.quality_scale, args.scalar_max_seconds = 1, 1, 64, 0.25, 10
        args.tte_runs = 1
    if not os.path.exists(PENUMBRA):
        sys.exit(f"mitsuba_compare: {PENUMBRA} not found; build Penumbra first (tools/setup)")
    os.makedirs(WORK, exist_ok=True)
    scenes = args.scenes or DEFAULT_SCENES
    if any("build/bench/" in s for s in scenes):
        subprocess.run([sys.executable, os.path.join(TOOLS, "scenes", "make_bench_scenes.py")], check=True, cwd=ROOT,
                       stdout=subprocess.DEVNULL)

    results_path = os.path.join(WORK, "results.json")
    reuse = {}
    if args.reuse_timings and os.path.exists(results_path):
        with open(results_path) as f:
            reuse = {x["name"]: x for x in json.load(f)}
    results = []
    for path in scenes:
        name = os.path.splitext(os.path.basename(path))[0]
        scene = load_scene(path)
        W, H = film_size(scene)
        r = {"name": name, "width": W, "height": H, "spp": scene_spp(scene), "notes": []}
        old = reuse.get(name)
        if old and all(old.get(k) for k in ("penumbra", "llvm")):
            log(f"[{name}] timings reused from {os.path.relpath(results_path, ROOT)}")
            for k in ("penumbra", "llvm", "scalar"):
                if old.get(k):
                    r[k] = old[k]
            r["notes"] = [n for n in old.get("notes", []) if "scalar_rgb timed" in n]
            r["reused"] = True
            r["timed_at"] = old.get("timed_at", "an earlier run")
            r["timed_load"] = old.get("timed_load")
        else:
            measure_timings(args, path, name, scene, r)
            r["timed_at"] = time.strftime("%Y-%m-%d %H:%M %Z")
            r["timed_load"] = list(os.getloadavg())
        if not args.skip_quality:
            quality(args, path, name, r)
        results.append(r)
        with open(results_path, "w") as f:
            json.dump(results, f, indent=1)

    text = report(machine_info(), results, args)
    print(text)
    if not args.no_doc:
        write_doc(text)
        log(f"updated {os.path.relpath(DOC, ROOT)}")


def measure_timings(args, path, name, scene, r):
    """Penumbra, then Mitsuba llvm_ad_rgb and scalar_rgb (each in a fresh process with a cold
    JIT cache): median render seconds, Msamples/s, start-up, and Penumbra's rays per sample."""
    W, H = film_size(scene)
    spp = scene_spp(scene)
    samples = W * H
    log(f"[{name}] Penumbra x{args.runs} at {spp} spp")
    times, startups = [], []
    for _ in range(args.runs):
        _, t, wall = penumbra_render(path, os.path.join(WORK, f"{name}_penumbra.exr"))
        times.append(t)
        startups.append(wall - t)
    med = statistics.median(times)
    rays = penumbra_rays_per_sample(path)
    r["penumbra"] = {"times": times, "median_s": med, "spp": spp, "msps": samples * spp / med * 1e-6,
                     "startup_s": statistics.median(startups), "rays_per_sample": rays,
                     "mrps": samples * spp * rays / med * 1e-6}
    for variant, key, runs in (("llvm_ad_rgb", "llvm", args.runs), ("scalar_rgb", "scalar", args.scalar_runs)):
        if key == "scalar" and args.skip_scalar:
            continue
        vspp = spp
        if key == "scalar":
            # Probe at 1 spp, then pick the spp that keeps one render near the limit.
            probe = run_worker({"op": "time", "variant": variant, "scene": path, "spp": 1, "runs": 1})
            per_spp = max(probe["times"][0], 1e-3)
            vspp = max(1, min(spp, int(args.scalar_max_seconds / per_spp)))
            if vspp != spp:
                plugins = " with Python plugins" if uses_python_plugins(scene) else ""
                r["notes"].append(f"{name}: Mitsuba scalar_rgb timed at {vspp} spp instead of {spp} "
                                  f"(about {per_spp:.1f} s per spp{plugins}); Msamples/s does not depend on spp")
        log(f"[{name}] Mitsuba {variant} x{runs} at {vspp} spp")
        m = run_worker({"op": "time", "variant": variant, "scene": path, "spp": vspp, "runs": runs}, cold_jit=True)
        med = statistics.median(m["times"])
        # Launch to scene ready, plus what the first render took beyond a steady one (JIT).
        m.update({"median_s": med, "spp": vspp, "msps": samples * vspp / med * 1e-6,
                  "startup_s": m["first_done_s"] - m["first_s"] + max(0.0, m["first_s"] - med)})
        r[key] = m


def quality(args, path, name, r):
    """Agreement of a Penumbra reference with two Mitsuba llvm renders at --quality-scale of
    the film, and for TTE_SCENES the time-to-error of both renderers with both samplers."""
    W, H = r["width"], r["height"]
    qW, qH = max(8, round(W * args.quality_scale)), max(8, round(H * args.quality_scale))
    log(f"[{name}] Penumbra reference {qW}x{qH} at {args.ref_spp} spp")
    ref, ref_path = penumbra_reference(path, name, args.ref_spp, qW, qH)
    mimgs = []
    for seed in (1, 2):
        out = os.path.join(WORK, f"{name}_mitsuba_{qW}x{qH}_{args.ref_spp}spp_s{seed}.exr")
        log(f"[{name}] Mitsuba llvm {qW}x{qH} at {args.ref_spp} spp, seed {seed}")
        run_worker({"op": "render", "variant": "llvm_ad_rgb", "scene": path, "spp": args.ref_spp,
                    "seed": seed, "out": out, "pass_samples": 4_000_000, "width": qW, "height": qH})
        mimgs.append(read_exr(out)[0])
    r["agreement"] = agree.agreement(ref, mimgs[0], mimgs[1])
    r["verdict"] = agree.verdict(r["agreement"])
    if r["verdict"] != "match":
        a = r["agreement"]
        w = a["worst_block"]
        msg = (f"MISMATCH on {name}: relMSE {a['relmse']:.4g} vs noise floor {a['noise_relmse']:.4g}, "
               f"block relMSE {a['block_relmse']:.4g} vs {a['block_noise_relmse']:.4g}, "
               f"mean ratio M/P {', '.join(f'{x:.3f}' for x in a['mean_ratio'])}; worst 8x8 block at "
               f"x={w['x']}, y={w['y']} of {w['image'][0]}x{w['image'][1]}: Penumbra "
               f"{[round(v, 4) for v in w['penumbra']]}, Mitsuba {[round(v, 4) for v in w['mitsuba']]}")
        r["notes"].append(msg)
        log("!" * 8 + " " + msg)
    if name not in TTE_SCENES:
        return
    # The reference's own noise (about half the Mitsuba-vs-Mitsuba floor) must stay small
    # against the target: at least 10 times smaller.
    target = max(args.target, 10 * 0.5 * r["agreement"]["noise_relmse"])
    log(f"[{name}] time-to-error, target relMSE {target:.4g}")
    pp = penumbra_tte(path, name, ref, target, args.max_spp, qW, qH, runs=args.tte_runs)
    pi = penumbra_tte(path, name, ref, target, args.max_spp, qW, qH, sampler="independent", runs=args.tte_runs)
    mitsuba_job = {"op": "tte", "variant": "llvm_ad_rgb", "scene": path, "ref": ref_path, "target": target,
                   "max_spp": args.max_spp, "width": qW, "height": qH, "pass_samples": 4_000_000,
                   "runs": args.tte_runs}
    mm = run_worker(mitsuba_job)["points"]
    ml = run_worker(dict(mitsuba_job, sampler="ldsampler"))["points"]
    r["tte"] = {"target": target, "penumbra_points": pp, "llvm_points": mm,
                "llvm_ld_points": ml, "llvm_ld_s": agree.time_to_error(ml, target),
                "penumbra_independent_points": pi,
                "penumbra_s": agree.time_to_error(pp, target), "llvm_s": agree.time_to_error(mm, target),
                "penumbra_independent_s": agree.time_to_error(pi, target)}
