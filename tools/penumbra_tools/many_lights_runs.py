"""Renders of the many-lights configurations, shared by tools/bench/bench-many-lights and
tools/figures/many_lights_figure.py (standard library only): a configuration is a Penumbra
light selection, optionally "+ris" for strategy ris ("bvh+ris"), or "mitsuba" / "mitsuba-ld",
Mitsuba 3 llvm_ad_rgb's direct integrator with emitter_samples=1, bsdf_samples=1 (Penumbra's
mis 1/1 with uniform emitter selection) and its `independent` or `ldsampler` sampler, run by
a long-lived worker (many_lights_mitsuba.py) that loads the scene once. Penumbra's
configurations use its default Owen-scrambled Sobol' sampler. Every render returns its
render seconds: Penumbra's from the EXR header (no start-up, no kernel compile), Mitsuba's
as the worker times them (mi.render + dr.eval/sync only)."""
import os
import struct
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))  # this file is tools/penumbra_tools/
PENUMBRA = os.path.join(ROOT, "build", "penumbra")
MITSUBA_SAMPLERS = {"mitsuba": "independent", "mitsuba-ld": "ldsampler"}
MITSUBA_WORKER = os.path.join(ROOT, "tools", "penumbra_tools", "many_lights_mitsuba.py")


def fail(message):
    sys.exit(f"{os.path.basename(sys.argv[0])}: {message}")


class Mitsuba:
    """The Mitsuba worker process: loads the scene once; each render() is one request, timed inside
    the worker (mi.render + dr.eval + dr.sync_thread only)."""

    def __init__(self, venv, scene, sampler):
        finder = os.path.join(ROOT, "tools", "mitsuba", "mitsuba-venv")
        p = subprocess.run([finder, "--find", venv], capture_output=True, text=True)
        if p.returncode != 0:
            fail(f"{p.stderr.strip()} (or leave the mitsuba configurations out)")
        env = dict(os.environ)
        key, _, value = p.stdout.strip().partition("=")
        env[key] = value
        self.proc = subprocess.Popen([os.path.join(venv, "bin", "python"), MITSUBA_WORKER, scene, sampler], env=env,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)

    def render(self, out, spp, seed, png=None):
        self.proc.stdin.write(f"{spp} {seed} {out}{' ' + png if png else ''}\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            fail(f"the Mitsuba worker ended (rendering {out})")
        return float(line)


def render_seconds(path):
    """penumbra:render_seconds from an OpenEXR header (attributes: name, type, size, value)."""
    with open(path, "rb") as f:
        b = f.read(1 << 16)
    i = 8
    while True:
        j = b.index(b"\0", i)
        name = b[i:j].decode()
        if not name:
            raise RuntimeError(f"{path}: no penumbra:render_seconds")
        k = b.index(b"\0", j + 1)
        typ = b[j + 1:k].decode()
        (n,) = struct.unpack("<i", b[k + 1:k + 5])
        value = b[k + 5:k + 5 + n]
        if name == "penumbra:render_seconds":
            return struct.unpack("<d" if typ == "double" else "<f", value)[0]
        i = k + 5 + n


class Runner:
    """Renders `scene` under any configuration; starts a Mitsuba worker per Mitsuba
    configuration named in `configs` (with the venv `mitsuba_venv`)."""

    def __init__(self, scene, configs, mitsuba_venv):
        self.scene = scene
        self.mitsuba = {c: Mitsuba(mitsuba_venv, scene, MITSUBA_SAMPLERS[c]) for c in configs if c in MITSUBA_SAMPLERS}

    def render(self, out, spp, config, seed, extra=(), scene=None, png=None):
        """Renders into out (an EXR) and, when png names one, an 8-bit sRGB PNG of it (penumbra
        render --png); returns the render seconds."""
        if config in self.mitsuba:
            return self.mitsuba[config].render(out, spp, seed, png)
        extra = [*extra, "--png", png] if png else extra
        selection, _, strategy = config.partition("+")
        strategy = ["--set", f"integrator.strategy={strategy}"] if strategy else []
        cmd = [PENUMBRA, "render", scene or self.scene, "-o", out, "--quiet", "--spp", str(spp), "--seed", str(seed),
               "--set", f"integrator.light_selection={selection}", *strategy, *extra]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            fail(f"{' '.join(cmd)} failed: {p.stderr.strip()}")
        return render_seconds(out)


def compare(a, ref):
    """`penumbra compare a ref` as a dict: relmse, rmse, mean_a, mean_b, max_abs."""
    p = subprocess.run([PENUMBRA, "compare", a, ref], capture_output=True, text=True, check=True)
    values = dict(line.split(maxsplit=1) for line in p.stdout.splitlines() if line.strip())
    if "relmse" not in values:
        raise RuntimeError("penumbra compare printed no relmse")
    return {k: float(v) for k, v in values.items()}


def relmse(a, ref):
    return compare(a, ref)["relmse"]
