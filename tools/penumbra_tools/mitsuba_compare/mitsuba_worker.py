"""One Mitsuba variant in a fresh process, driven by a JSON job on the command line
(`tools/mitsuba/mitsuba_compare.py --worker JOB`): time renders, render an image, or render at
rising spp until an error target (time-to-error). The process prints one RESULT line."""
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

from penumbra_tools.mitsuba_compare.images import read_exr, relmse, write_exr
from penumbra_tools.mitsuba_compare.paths import ENTRY, TOOLS, WORK
from penumbra_tools.mitsuba_compare.scenes import film_size, load_scene


def process_cpu_seconds():
    """User and system CPU time of this process, all its threads."""
    import resource
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def worker(job):
    t_start = job["launched"]
    import numpy as np
    import mitsuba as mi
    mi.set_variant(job["variant"])
    sys.path.insert(0, TOOLS)
    from penumbra_tools import mitsuba_penumbra as mp

    scene_json = load_scene(job["scene"], job.get("width"), job.get("height"))
    t_import = time.time() - t_start

    def make(spp, seed=0):
        return mi.load_dict(mp.translate(scene_json, spp=spp, seed=seed, sampler=job.get("sampler", "independent"),
                                         base_dir=os.path.dirname(os.path.abspath(job["scene"]))))

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
        times, cpu_times = [], []
        for r in range(job["runs"]):
            c0 = process_cpu_seconds()
            _, t = render(scene, spp, r + 1)
            cpu_times.append(process_cpu_seconds() - c0)
            times.append(t)
        out["times"] = times
        out["cpu_times"] = cpu_times  # all threads (Dr.Jit's pool): steadier on a shared machine
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
            # The median of `runs` renders of the same image (same seed), as for Penumbra.
            times = []
            for _ in range(max(1, job.get("runs", 1))):
                img, t = render(scene, spp, 7 + spp, job.get("pass_samples"))
                times.append(t)
            e = relmse(img, ref)
            points.append([spp, statistics.median(times), e])
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
    try:
        p = subprocess.run([sys.executable, ENTRY, "--worker", json.dumps(job)], capture_output=True,
                           text=True, timeout=timeout, env=env)
    finally:
        if tmp_home:
            shutil.rmtree(tmp_home, ignore_errors=True)
    for line in p.stdout.splitlines():
        if "RESULT " in line:  # Mitsuba's log may leave a colour escape code before it
            return json.loads(line[line.index("RESULT ") + 7:])
    raise RuntimeError(f"Mitsuba worker {job['op']} {job['variant']} failed (exit {p.returncode}):\n"
                       + (p.stderr or p.stdout)[-3000:])
