"""Whole-process start-up, side by side: `penumbra render` against a fresh Python process
that imports Mitsuba 3, loads the same scene (tools/penumbra_tools/mitsuba_penumbra.py's translation),
renders and writes the EXR, as a user of each would run one small image. Both with their
disk caches warm (one untimed run each first). Per scene: the median wall time and the
median peak resident memory of `--runs` alternating runs, and Penumbra's phases
(PENUMBRA_PHASES: load, context, renderer, first_dispatch, render, write) from one more run.

Run through tools/bench/bench-startup, which makes the Python environment Mitsuba needs.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
TOOLS = os.path.join(ROOT, "tools")
PENUMBRA = os.path.join(ROOT, "build", "penumbra")

# (scene, width, height): the Cornell box at the size of a quick look, the MIS scene and the
# million-triangle displaced plane (tools/scenes/make_bench_scenes.py) at their own sizes.
DEFAULT_SCENES = [("scenes/cornell.json", 160, 120), ("scenes/veach_mis.json", None, None),
                  ("build/bench/displaced_1m.json", None, None)]

# The Mitsuba process, timed from its start like Penumbra's: import, load_dict, render, write.
MITSUBA_CHILD = r"""
import json, sys
sys.path.insert(0, {tools!r})
import mitsuba as mi
mi.set_variant("llvm_ad_rgb")
from penumbra_tools import mitsuba_penumbra as mp
with open({scene!r}) as f:
    scene = json.load(f)
if {width!r}:
    scene.setdefault("film", {{}})["width"] = {width!r}
    scene["film"]["height"] = {height!r}
img = mi.render(mi.load_dict(mp.translate(scene, spp={spp!r}, seed=0, sampler="independent")), spp={spp!r})
mi.Bitmap(img).write({out!r})
"""


def run_measured(cmd, env=None):
    """Runs `cmd` to completion; returns (wall seconds, peak RSS MiB, stderr text)."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, cwd=ROOT)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    err = p.stderr.read().decode(errors="replace")
    p.stderr.close()
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        sys.exit(f"bench-startup: {' '.join(cmd)} failed ({p.returncode}): {err.strip()[-400:]}")
    return wall, usage.ru_maxrss / 1024.0, err


def penumbra_cmd(scene, width, height, spp, out):
    cmd = [PENUMBRA, "render", scene, "--spp", str(spp), "-o", out, "--quiet"]
    if width:
        cmd += ["--width", str(width), "--height", str(height)]
    return cmd


def mitsuba_cmd(python, scene, width, height, spp, out):
    code = MITSUBA_CHILD.format(tools=TOOLS, scene=os.path.join(ROOT, scene), width=width, height=height,
                                spp=spp, out=out)
    return [python, "-c", code]


def phases(scene, width, height, spp, out):
    env = dict(os.environ, PENUMBRA_PHASES="1")
    _, _, err = run_measured(penumbra_cmd(scene, width, height, spp, out), env)
    rows = []
    for line in err.splitlines():
        # "penumbra: phase NAME S s, rss X MiB, peak Y MiB"
        parts = line.split()
        if len(parts) >= 10 and parts[1] == "phase":
            rows.append((parts[2], float(parts[3]), float(parts[9])))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=5, help="alternating runs per program and scene (default 5)")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--python", default=os.path.join(ROOT, "build", "venv-mitsuba", "bin", "python"),
                    help="a Python with mitsuba 3 (tools/bench/bench-startup makes it)")
    ap.add_argument("--scenes", nargs="+", help="scene files (at their own film size)")
    ap.add_argument("--json", help="also write the results here")
    args = ap.parse_args()
    scenes = [(s, None, None) for s in args.scenes] if args.scenes else DEFAULT_SCENES
    if any("build/bench/" in s for s, _, _ in scenes):
        subprocess.run([sys.executable, os.path.join(TOOLS, "scenes", "make_bench_scenes.py")], check=True, cwd=ROOT,
                       stdout=subprocess.DEVNULL)
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene, width, height in scenes:
            p_out, m_out = os.path.join(tmp, "p.exr"), os.path.join(tmp, "m.exr")
            pc = penumbra_cmd(scene, width, height, args.spp, p_out)
            mc = mitsuba_cmd(args.python, scene, width, height, args.spp, m_out)
            run_measured(pc)  # warm the disk caches, untimed
            run_measured(mc)
            p, m = [], []
            for _ in range(args.runs):  # alternating, so that load drifts hit both alike
                p.append(run_measured(pc)[:2])
                m.append(run_measured(mc)[:2])
            r = {"scene": scene, "size": f"{width}x{height}" if width else "own", "spp": args.spp,
                 "penumbra_wall_s": statistics.median(x[0] for x in p),
                 "penumbra_peak_mib": statistics.median(x[1] for x in p),
                 "mitsuba_wall_s": statistics.median(x[0] for x in m),
                 "mitsuba_peak_mib": statistics.median(x[1] for x in m),
                 "phases": phases(scene, width, height, args.spp, p_out)}
            results.append(r)
            print(f"bench-startup: {scene}: penumbra {r['penumbra_wall_s']:.3f} s, {r['penumbra_peak_mib']:.0f} MiB; "
                  f"mitsuba {r['mitsuba_wall_s']:.3f} s, {r['mitsuba_peak_mib']:.0f} MiB", file=sys.stderr, flush=True)

    print(f"Whole process, one image at {args.spp} spp, median of {args.runs} alternating runs, disk caches warm:\n")
    print("| scene | Penumbra wall | Mitsuba 3 llvm wall | ratio (Mitsuba / Penumbra) | Penumbra peak | Mitsuba peak |")
    print("|---|---|---|---|---|---|")
    for r in results:
        print(f"| {r['scene']} ({r['size']}) | {r['penumbra_wall_s']:.3f} s | {r['mitsuba_wall_s']:.3f} s | "
              f"{r['mitsuba_wall_s'] / r['penumbra_wall_s']:.2f}x | {r['penumbra_peak_mib']:.0f} MiB | "
              f"{r['mitsuba_peak_mib']:.0f} MiB |")
    print("\nPenumbra's phases (one run; seconds, peak MiB after the phase):\n")
    for r in results:
        print(f"- {r['scene']}: " + ", ".join(f"{n} {s:.3f} s ({pk:.0f} MiB)" for n, s, pk in r["phases"]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
