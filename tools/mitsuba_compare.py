#!/usr/bin/env python3
"""Penumbra vs Mitsuba 3 on the same machine: throughput, start-up, image agreement and
time-to-error for the benchmark scenes. Run it through tools/bench-mitsuba, which makes the
Python environment it needs (build/venv-mitsuba: mitsuba 3.9.1, numpy; Debian's libllvm19).

  tools/bench-mitsuba [--runs 5] [--scenes A.json B.json ...] [--quick] [--no-doc]

Per scene:
  * Penumbra: `build/penumbra render` --runs times at the scene's spp; render time is the
    EXR header's penumbra:render_seconds (median), start-up is wall time minus render time.
  * Mitsuba llvm_ad_rgb and scalar_rgb, each in a fresh process: scene load, first render
    (JIT compilation for llvm) reported as start-up, then the median of --runs renders
    (scalar: --scalar-runs, and fewer spp where Python plugins make it slow).
  * Agreement (at --quality-scale of the film size): a Penumbra reference of --ref-spp is
    compared with a Mitsuba llvm render of the same spp (relMSE, relMSE of 8x8 block
    means, per-channel mean ratio, worst block), next to the noise floor: two independent
    Mitsuba renders of that spp compared with each other.
  * Time-to-error (Cornell box and MIS scene): renders at 1, 2, 4, ... spp until the relMSE
    against the Penumbra reference drops below --target; the time at the target is
    interpolated log-log between the two bracketing renders. Penumbra with its Sobol'
    default and with the independent sampler; Mitsuba llvm with independent and ldsampler.
Writes a markdown report to stdout and into docs/PERFORMANCE.md (section "Results").
"""
import argparse
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
TOOLS = os.path.join(ROOT, "tools")
PENUMBRA = os.path.join(ROOT, "build", "penumbra")
PENUMBRA_BENCH = os.path.join(ROOT, "build", "penumbra_bench")
WORK = os.path.join(ROOT, "build", "mitsuba-compare")
DOC = os.path.join(ROOT, "docs", "PERFORMANCE.md")
INSTALL_HINT = "run tools/bench-mitsuba (it makes build/venv-mitsuba with mitsuba 3.9.1 and numpy, and installs libllvm19)"
DEFAULT_SCENES = ["scenes/cornell.json", "scenes/veach_mis.json", "build/bench/displaced_1m.json"]
TTE_SCENES = ("cornell", "veach_mis")


def need_imports():
    try:
        import numpy  # noqa: F401
        import mitsuba  # noqa: F401
    except ImportError as e:
        sys.exit(f"mitsuba_compare: {e}; {INSTALL_HINT}")


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def load_scene(path, width=None, height=None):
    with open(path) as f:
        scene = json.load(f)
    if width:
        scene.setdefault("film", {})["width"] = width
        scene["film"]["height"] = height
    return scene


def film_size(scene):
    f = scene.get("film", {})
    return int(f.get("width", 512)), int(f.get("height", 512))


def scene_spp(scene):
    return int(scene.get("sampler", {}).get("spp", 16))


def relmse(a, b):
    """mean of (a-b)^2/(b^2+1e-2), b the reference (as `penumbra compare`)."""
    import numpy as np
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return float(np.mean((a - b) ** 2 / (b * b + 1e-2)))


def read_exr(path):
    import numpy as np
    import mitsuba as mi
    if not mi.variant():
        mi.set_variant("scalar_rgb")
    bmp = mi.Bitmap(path)
    meta = bmp.metadata()
    img = np.array(mi.TensorXf(bmp), dtype=np.float32)[:, :, :3]
    keys = meta.keys()
    return img, {k: meta[k] for k in keys}


def write_exr(path, img):
    import numpy as np
    import mitsuba as mi
    tmp = path + ".tmp.exr"
    mi.Bitmap(np.ascontiguousarray(img, dtype=np.float32)).write(tmp)
    os.replace(tmp, path)


# ---------------------------------------------------------------------------------------
# Worker: one Mitsuba variant in a fresh process, driven by a JSON job on the command line.
# ---------------------------------------------------------------------------------------
def worker(job):
    t_start = job["launched"]
    import numpy as np
    import drjit as dr
    import mitsuba as mi
    mi.set_variant(job["variant"])
    sys.path.insert(0, TOOLS)
    import mitsuba_penumbra as mp

    scene_json = load_scene(job["scene"], job.get("width"), job.get("height"))
    t_import = time.time() - t_start

    def make(spp, seed=0):
        return mi.load_dict(mp.translate(scene_json, spp=spp, seed=seed, sampler=job.get("sampler", "independent")))

    def render(scene, spp, seed, pass_samples=None):
        """Renders spp samples per pixel, in passes of at most pass_samples samples in all
        (Mitsuba's llvm wavefront holds every sample at once), and returns (image, seconds)."""
        W, H = film_size(scene_json)
        per_pass = spp if not pass_samples else max(1, min(spp, pass_samples // (W * H)))
        t0 = time.perf_counter()
        acc, done, k = None, 0, 0
        while done < spp:
            n = min(per_pass, spp - done)
            img = mi.render(scene, spp=n, seed=seed * 100003 + k)
            arr = np.array(img, dtype=np.float64)
            acc = arr * n if acc is None else acc + arr * n
            done += n
            k += 1
        return (acc / spp).astype(np.float32), time.perf_counter() - t0

    out = {"variant": job["variant"], "import_s": t_import}
    op = job["op"]
    if op == "time":
        spp = job["spp"]
        t0 = time.perf_counter()
        scene = make(spp)
        out["load_s"] = time.perf_counter() - t0
        _, out["first_s"] = render(scene, spp, 0)
        out["first_done_s"] = time.time() - t_start
        times = []
        for r in range(job["runs"]):
            _, t = render(scene, spp, r + 1)
            times.append(t)
        out["times"] = times
    elif op == "render":
        scene = make(job["spp"])
        img, out["seconds"] = render(scene, job["spp"], job["seed"], job.get("pass_samples"))
        write_exr(job["out"], img)
    elif op == "tte":
        ref, _ = read_exr(job["ref"])
        points = []
        # ldsampler takes only square powers of two (it rounds others up): 4, 16, 64, ...
        ld = job.get("sampler") == "ldsampler"
        spp = 4 if ld else 1
        while spp <= job["max_spp"]:
            scene = make(spp)  # the sampler's sample_count matters to low-discrepancy samplers
            render(scene, spp, 999, job.get("pass_samples"))  # a new spp may compile a new kernel: untimed
            img, t = render(scene, spp, 7 + spp, job.get("pass_samples"))
            e = relmse(img, ref)
            points.append([spp, t, e])
            if e < job["target"]:
                break
            spp *= 4 if ld else 2
        out["points"] = points
    print("RESULT " + json.dumps(out), flush=True)


def run_worker(job, timeout=3600, cold_jit=False):
    """Runs a job in a fresh process. cold_jit: give it an empty Dr.Jit kernel cache (the cache
    lives in $HOME/.drjit), so that its first render pays the full JIT compilation."""
    env = dict(os.environ)
    tmp_home = None
    if cold_jit:
        tmp_home = os.path.join(WORK, f"home-{os.getpid()}-{time.time_ns()}")
        os.makedirs(tmp_home)
        env["HOME"] = tmp_home
    job = dict(job, launched=time.time())
    py = sys.executable
    try:
        p = subprocess.run([py, os.path.abspath(__file__), "--worker", json.dumps(job)], capture_output=True,
                           text=True, timeout=timeout, env=env)
    finally:
        if tmp_home:
            shutil.rmtree(tmp_home, ignore_errors=True)
    for line in p.stdout.splitlines():
        if "RESULT " in line:  # Mitsuba's log may leave a colour escape code before it
            return json.loads(line[line.index("RESULT ") + 7:])
    raise RuntimeError(f"Mitsuba worker {job['op']} {job['variant']} failed (exit {p.returncode}):\n"
                       + (p.stderr or p.stdout)[-3000:])


# ---------------------------------------------------------------------------------------
# Penumbra
# ---------------------------------------------------------------------------------------
def penumbra_render(scene_path, out, spp=None, seed=None, width=None, height=None, sampler=None):
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
    """High-spp Penumbra image, cached in build/mitsuba-compare by its parameters."""
    out = os.path.join(WORK, f"{name}_ref_{width}x{height}_{spp}spp_s{seed}.exr")
    if os.path.exists(out) and os.path.getmtime(out) > os.path.getmtime(scene_path) \
            and os.path.getmtime(out) > os.path.getmtime(PENUMBRA):
        return read_exr(out)[0], out, None
    img, t, _ = penumbra_render(scene_path, out, spp=spp, seed=seed, width=width, height=height)
    return img, out, t


def penumbra_tte(scene_path, name, ref, target, max_spp, width, height, sampler=None):
    points = []
    spp = 1
    while spp <= max_spp:
        out = os.path.join(WORK, f"{name}_tte_penumbra.exr")
        img, t, _ = penumbra_render(scene_path, out, spp=spp, seed=17 + spp, width=width, height=height,
                                    sampler=sampler)
        e = relmse(img, ref)
        points.append([spp, t, e])
        if e < target:
            break
        spp *= 2
    return points


def time_to_error(points, target):
    """Seconds at which relMSE reaches target, log-log interpolated between the renders that
    bracket it; None when the last render is still above it."""
    for i, (spp, t, e) in enumerate(points):
        if e < target:
            if i == 0:
                return t * e / target if e > 0 else t  # error ~ 1/time: extrapolate down
            s0, t0, e0 = points[i - 1]
            f = (math.log(target) - math.log(e0)) / (math.log(e) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t) - math.log(t0)))
    return None


# ---------------------------------------------------------------------------------------
# Agreement statistics
# ---------------------------------------------------------------------------------------
def block_means(img, b=8):
    import numpy as np
    H, W, C = img.shape
    h, w = H // b, W // b
    return img[:h * b, :w * b].reshape(h, b, w, b, C).mean(axis=(1, 3))


def agreement(ref, m1, m2):
    import numpy as np
    bp, b1, b2 = block_means(ref), block_means(m1), block_means(m2)
    d = np.abs(b1 - bp).mean(axis=2) / (bp.mean(axis=2) + 0.05)
    # Worst block judged against the noise between the two Mitsuba renders there.
    noise = np.abs(b1 - b2).mean(axis=2) / (bp.mean(axis=2) + 0.05) + 1e-6
    z = d / np.maximum(noise, np.median(noise))
    by, bx = np.unravel_index(np.argmax(z), z.shape)
    H, W, _ = ref.shape
    return {
        "relmse": relmse(m1, ref),
        "noise_relmse": relmse(m1, m2),
        "block_relmse": relmse(b1, bp),
        "block_noise_relmse": relmse(b1, b2),
        "mean_ratio": [float(m1[..., c].mean() / max(ref[..., c].mean(), 1e-12)) for c in range(3)],
        "worst_block": {"x": int(bx * 8), "y": int(by * 8), "size": 8, "rel_diff": float(d[by, bx]),
                        "noise": float(noise[by, bx]), "penumbra": bp[by, bx].tolist(),
                        "mitsuba": b1[by, bx].tolist(), "image": [W, H]},
    }


def verdict(a):
    """Match when the difference Penumbra-Mitsuba looks like noise: relMSE not much above the
    Mitsuba-vs-Mitsuba floor, 8x8 block means likewise, mean ratios within 2%."""
    ok = a["relmse"] < 3 * a["noise_relmse"] + 1e-4 and a["block_relmse"] < 4 * a["block_noise_relmse"] + 1e-4 \
        and all(abs(r - 1) < 0.02 for r in a["mean_ratio"])
    return "match" if ok else "MISMATCH"


# ---------------------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------------------
def machine_info():
    import mitsuba as mi
    model = platform.processor()
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        m = re.search(r"Model name:\s*(.+)", out)
        model = m.group(1).strip() if m else model
    except OSError:
        pass
    dev = " ".join(line.strip() for line in
                   subprocess.run([PENUMBRA, "devices"], capture_output=True, text=True).stdout.splitlines())
    mesa = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "mesa-vulkan-drivers"], capture_output=True,
                          text=True).stdout.strip()
    import drjit as dr
    return {"cpu": model, "cores": os.cpu_count(), "device": dev, "mesa": mesa, "mitsuba": mi.__version__,
            "drjit": dr.__version__, "llvm": os.environ.get("DRJIT_LIBLLVM_PATH", "(default)"),
            "load": os.getloadavg(), "date": time.strftime("%Y-%m-%d %H:%M %Z")}


def fmt(x, d=2):
    if x is None:
        return "n/a"
    if isinstance(x, str):
        return x
    if x != 0 and (abs(x) < 10 ** -d or abs(x) >= 1e5):
        return f"{x:.2e}"
    return f"{x:.{d}f}"


def report(info, results, args):
    L = []
    L.append(f"Measured {info['date']} by `tools/bench-mitsuba{' ' + ' '.join(args.argv) if args.argv else ''}`.")
    reused = [r["name"] for r in results if r.get("reused")]
    if reused:
        when = sorted({r["timed_at"] for r in results if r.get("reused")})
        L.append(f"Throughput and start-up of {', '.join(reused)} come from the previous full run "
                 f"({', '.join(when)}, build/mitsuba-compare/results.json); agreement and time-to-error "
                 "were measured now.")
    L.append("")
    L.append(f"- CPU: {info['cpu']}, {info['cores']} cores (load average at the end: "
             f"{', '.join(f'{x:.1f}' for x in info['load'])}; the machine is shared, so timings are noisy: medians)")
    L.append(f"- Penumbra device: {info['device'].lstrip('* ')}; Mesa {info['mesa']}")
    L.append(f"- Mitsuba {info['mitsuba']} (Dr.Jit {info['drjit']}), llvm_ad_rgb on {os.path.basename(info['llvm'])}, "
             f"and scalar_rgb")
    L.append("")
    L.append("Throughput (median of the timed renders, Msamples/s = width x height x spp / render time; "
             "ratio = Penumbra / Mitsuba; Penumbra's rays per sample (camera, shadow and BRDF rays) are counted "
             "by `penumbra_bench --count-rays`, Mitsuba's `direct` integrator traces the same rays per sample, so "
             "its Mrays/s is its Msamples/s times Penumbra's rays per sample):")
    L.append("")
    L.append("| scene | res, spp | Penumbra Ms/s | Mitsuba llvm Ms/s | Mitsuba scalar Ms/s | Penumbra/llvm | "
             "Penumbra/scalar | rays/sample | Mrays/s: Penumbra / llvm | start-up s: Penumbra / llvm / scalar |")
    L.append("|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        p, ml, ms = r["penumbra"], r.get("llvm"), r.get("scalar")
        sp = lambda m: m["msps"] if m else None  # noqa: E731
        ratio = lambda a, b: f"{a / b:.2f}" if a and b else "n/a"  # noqa: E731
        scal = fmt(sp(ms)) + (f" ({ms['spp']} spp)" if ms and ms["spp"] != r["spp"] else "")
        rps = p.get("rays_per_sample")
        rays = (f"{rps:.2f} | {fmt(p['mrps'])} / {fmt(sp(ml) * rps if ml else None)}" if rps else "n/a | n/a")
        L.append(f"| {r['name']} | {r['width']}x{r['height']}, {r['spp']} | {fmt(sp(p))} | {fmt(sp(ml))} | {scal} | "
                 f"{ratio(sp(p), sp(ml))} | {ratio(sp(p), sp(ms))} | {rays} | "
                 f"{fmt(p['startup_s'], 1)} / {fmt(ml and ml['startup_s'], 1)} / {fmt(ms and ms['startup_s'], 1)} |")
    L.append("")
    L.append("Render seconds (median, all runs in brackets) and start-up detail:")
    L.append("")
    for r in results:
        for key, label in (("penumbra", "Penumbra"), ("llvm", "Mitsuba llvm"), ("scalar", "Mitsuba scalar")):
            m = r.get(key)
            if not m:
                continue
            extra = ""
            if key != "penumbra":
                extra = f"; import {m['import_s']:.2f} s, scene load {m['load_s']:.2f} s, first render {m['first_s']:.2f} s"
            L.append(f"- {r['name']}, {label}: {m['median_s']:.3f} s [{', '.join(f'{t:.2f}' for t in m['times'])}] "
                     f"at {m['spp']} spp; start-up {m['startup_s']:.2f} s{extra}")
    L.append("")
    L.append(f"Image agreement at {args.quality_scale:g} x film size: Penumbra reference ({args.ref_spp} spp, seed 4242) "
             f"vs Mitsuba llvm ({args.ref_spp} spp); noise floor = two independent Mitsuba renders of "
             f"{args.ref_spp} spp compared with each other. Block = 8x8 pixel means. Verdict: match when "
             "relMSE <= 3x floor, block relMSE <= 4x block floor and channel means within 2%.")
    L.append("")
    L.append("| scene | relMSE P vs M | floor M vs M | block relMSE | block floor | mean ratio M/P (r,g,b) | "
             "worst 8x8 block (x,y): rel. diff / noise | verdict |")
    L.append("|---|---|---|---|---|---|---|---|")
    for r in results:
        a = r.get("agreement")
        if not a:
            continue
        w = a["worst_block"]
        L.append(f"| {r['name']} | {fmt(a['relmse'], 4)} | {fmt(a['noise_relmse'], 4)} | {fmt(a['block_relmse'], 5)} | "
                 f"{fmt(a['block_noise_relmse'], 5)} | {', '.join(f'{x:.3f}' for x in a['mean_ratio'])} | "
                 f"({w['x']},{w['y']}) of {w['image'][0]}x{w['image'][1]}: {w['rel_diff']:.3f} / {w['noise']:.3f} | "
                 f"**{r['verdict']}** |")
    L.append("")
    tte = [r for r in results if r.get("tte")]
    if tte:
        L.append(f"Time-to-error at {args.quality_scale:g} x film size: render seconds (excluding start-up) to reach "
                 f"the target relMSE against the Penumbra reference ({args.target:g}, or 10x the reference's own "
                 "noise where that is larger), log-log interpolated between the renders at 1, 2, 4, ... spp "
                 "that bracket the first render below it (spp, seconds, relMSE of each render in brackets; "
                 "single renders, so a firefly can make one level worse than the one before):")
        L.append("")
        L.append("Penumbra renders with its default sampler (Owen-scrambled Sobol') and with `sampler.type` "
                 "independent; Mitsuba llvm with its default `independent` sampler and with its low-discrepancy "
                 "`ldsampler`. Ratios are Penumbra Sobol' over each Mitsuba variant.")
        L.append("")
        L.append("| scene | target relMSE | Penumbra Sobol' s | Penumbra independent s | Mitsuba llvm independent s | "
                 "Mitsuba llvm ldsampler s | Penumbra / llvm independent | Penumbra / llvm ldsampler |")
        L.append("|---|---|---|---|---|---|---|---|")
        for r in tte:
            tp, ti = r["tte"]["penumbra_s"], r["tte"].get("penumbra_independent_s")
            tm, tl = r["tte"]["llvm_s"], r["tte"].get("llvm_ld_s")
            q = lambda a, b: f"{a / b:.2f}" if a and b else "n/a"  # noqa: E731
            L.append(f"| {r['name']} | {r['tte']['target']:.4g} | {fmt(tp, 3)} | {fmt(ti, 3)} | {fmt(tm, 3)} | "
                     f"{fmt(tl, 3)} | {q(tp, tm)} | {q(tp, tl)} |")
        L.append("")
        for r in tte:
            for key in ("penumbra", "penumbra_independent", "llvm", "llvm_ld"):
                pts = r["tte"].get(key + "_points")
                if pts is None:
                    continue
                L.append(f"- {r['name']} {key}: " + ", ".join(f"({s}, {t:.3f}, {e:.4f})" for s, t, e in pts))
        L.append("")
    notes = [n for r in results for n in r.get("notes", [])]
    if notes:
        L.append("Notes:")
        L.append("")
        L += [f"- {n}" for n in notes]
        L.append("")
    return "\n".join(L)


def write_doc(text):
    os.makedirs(os.path.dirname(DOC), exist_ok=True)
    doc = open(DOC).read() if os.path.exists(DOC) else "# Performance\n\n## Results\n\n"
    begin, end = "<!-- results:begin -->", "<!-- results:end -->"
    block = f"{begin}\n{text}\n{end}"
    if begin in doc and end in doc:
        doc = doc[:doc.index(begin)] + block + doc[doc.index(end) + len(end):]
    elif "## Results" in doc:
        i = doc.index("## Results") + len("## Results")
        doc = doc[:i] + "\n\n" + block + doc[i:]
    else:
        doc += "\n## Results\n\n" + block + "\n"
    with open(DOC, "w") as f:
        f.write(doc)


# ---------------------------------------------------------------------------------------
def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
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
    args.argv = [a for a in sys.argv[1:]]
    need_imports()
    if args.quick:
        args.runs, args.scalar_runs, args.ref_spp, args.quality_scale, args.scalar_max_seconds = 1, 1, 64, 0.25, 10
    if not os.path.exists(PENUMBRA):
        sys.exit(f"mitsuba_compare: {PENUMBRA} not found; build Penumbra first (tools/setup)")
    os.makedirs(WORK, exist_ok=True)
    scenes = args.scenes or DEFAULT_SCENES
    if any("build/bench/" in s for s in scenes):
        subprocess.run([sys.executable, os.path.join(TOOLS, "make_bench_scenes.py")], check=True, cwd=ROOT,
                       stdout=subprocess.DEVNULL)
    sys.path.insert(0, TOOLS)
    import numpy as np  # noqa: F401

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
        spp = scene_spp(scene)
        r = {"name": name, "width": W, "height": H, "spp": spp, "notes": []}
        uses_python = scene.get("integrator", {}).get("type") == "ao" or any(
            m.get("type") == "phong" for m in scene.get("materials", {}).values())
        samples = W * H
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
            measure_timings(args, path, name, scene, r, uses_python)
            r["timed_at"] = time.strftime("%Y-%m-%d %H:%M %Z")
            r["timed_load"] = list(os.getloadavg())
        quality(args, path, name, r)
        results.append(r)
        with open(results_path, "w") as f:
            json.dump(results, f, indent=1)

    info = machine_info()
    text = report(info, results, args)
    print(text)
    if not args.no_doc:
        write_doc(text)
        log(f"updated {os.path.relpath(DOC, ROOT)}")


def measure_timings(args, path, name, scene, r, uses_python):
    W, H = film_size(scene)
    spp = scene_spp(scene)
    samples = W * H
    if True:
        # --- Penumbra timing
        log(f"[{name}] Penumbra x{args.runs} at {spp} spp")
        times, startups = [], []
        for k in range(args.runs):
            _, t, wall = penumbra_render(path, os.path.join(WORK, f"{name}_penumbra.exr"))
            times.append(t)
            startups.append(wall - t)
        med = statistics.median(times)
        rays = penumbra_rays_per_sample(path)
        r["penumbra"] = {"times": times, "median_s": med, "spp": spp, "msps": samples * spp / med * 1e-6,
                         "startup_s": statistics.median(startups), "rays_per_sample": rays,
                         "mrps": samples * spp * rays / med * 1e-6}
        # --- Mitsuba timing
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
                    r["notes"].append(f"{name}: Mitsuba scalar_rgb timed at {vspp} spp instead of {spp} "
                                      f"(about {per_spp:.1f} s per spp{' with Python plugins' if uses_python else ''}); "
                                      "Msamples/s does not depend on spp")
            log(f"[{name}] Mitsuba {variant} x{runs} at {vspp} spp")
            m = run_worker({"op": "time", "variant": variant, "scene": path, "spp": vspp, "runs": runs}, cold_jit=True)
            med = statistics.median(m["times"])
            # Launch to scene ready, plus what the first render took beyond a steady one (JIT).
            m.update({"median_s": med, "spp": vspp, "msps": samples * vspp / med * 1e-6,
                      "startup_s": m["first_done_s"] - m["first_s"] + max(0.0, m["first_s"] - med)})
            r[key] = m


def quality(args, path, name, r):
    W, H = r["width"], r["height"]
    if True:
        # --- Agreement and time-to-error at quality scale
        if not args.skip_quality:
            qW, qH = max(8, round(W * args.quality_scale)), max(8, round(H * args.quality_scale))
            log(f"[{name}] Penumbra reference {qW}x{qH} at {args.ref_spp} spp")
            ref, ref_path, t_ref = penumbra_reference(path, name, args.ref_spp, qW, qH)
            mimgs = []
            for seed in (1, 2):
                out = os.path.join(WORK, f"{name}_mitsuba_{qW}x{qH}_{args.ref_spp}spp_s{seed}.exr")
                log(f"[{name}] Mitsuba llvm {qW}x{qH} at {args.ref_spp} spp, seed {seed}")
                run_worker({"op": "render", "variant": "llvm_ad_rgb", "scene": path, "spp": args.ref_spp,
                            "seed": seed, "out": out, "pass_samples": 4_000_000, "width": qW, "height": qH})
                mimgs.append(read_exr(out)[0])
            r["agreement"] = agreement(ref, mimgs[0], mimgs[1])
            r["verdict"] = verdict(r["agreement"])
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
            if name in TTE_SCENES:
                # The reference's own noise (about half the Mitsuba-vs-Mitsuba floor) must stay
                # small against the target: at least 10 times smaller.
                target = max(args.target, 10 * 0.5 * r["agreement"]["noise_relmse"])
                log(f"[{name}] time-to-error, target relMSE {target:.4g}")
                pp = penumbra_tte(path, name, ref, target, args.max_spp, qW, qH)
                pi = penumbra_tte(path, name, ref, target, args.max_spp, qW, qH, sampler="independent")
                mm = run_worker({"op": "tte", "variant": "llvm_ad_rgb", "scene": path, "ref": ref_path,
                                 "target": target, "max_spp": args.max_spp, "width": qW, "height": qH,
                                 "pass_samples": 4_000_000})["points"]
                ml = run_worker({"op": "tte", "variant": "llvm_ad_rgb", "scene": path, "ref": ref_path,
                                 "target": target, "max_spp": args.max_spp, "width": qW, "height": qH,
                                 "pass_samples": 4_000_000, "sampler": "ldsampler"})["points"]
                r["tte"] = {"target": target, "penumbra_points": pp, "llvm_points": mm,
                            "llvm_ld_points": ml, "llvm_ld_s": time_to_error(ml, target),
                            "penumbra_independent_points": pi,
                            "penumbra_s": time_to_error(pp, target), "llvm_s": time_to_error(mm, target),
                            "penumbra_independent_s": time_to_error(pi, target)}


if __name__ == "__main__":
    main()
