#!/usr/bin/env python3
"""What textures cost a render: CPU seconds of the Cornell box (scenes/cornell.json, 200 x 200)
untextured and textured (every albedo times a 1024 x 1024 noise PNG: the worst case, a
lookup at every shading point into a texture far larger than the caches) under two builds
A and B (e.g. main's and this one's, to compare two texture paths; untextured kernels
should cost the same). A build without textures is given with --a-untextured-only.

CPU time (user + system of the render process and its llvmpipe threads) is measured rather
than wall time, which varies 3x between identical runs on a shared machine; the difference
between a 68-spp and a 4-spp render removes start-up and kernel compilation. The builds
alternate within each round; medians of the rounds and of the per-round ratios.

Usage: tools/texture_cost.py [--a A/penumbra] [--b B/penumbra] [--rounds N] [--a-untextured-only]
"""
import argparse
import glob
import json
import os
import random
import statistics
import struct
import subprocess
import tempfile
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def noise_png(path, size=1024, seed=1):
    """An 8-bit RGB PNG of grey noise in [128, 255] (stdlib zlib; no image library)."""
    rng = random.Random(seed)
    rows = b"".join(b"\x00" + bytes(rng.randint(128, 255) for _ in range(size * 3)) for _ in range(size))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", size, size, 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows, 6)) + chunk(b"IEND", b""))


def cpu_seconds(exe, scene, spp, out, env):
    before = os.times()
    subprocess.run([exe, "render", scene, "-o", out, "--quiet", "--spp", str(spp), "--width", "200", "--height", "200"],
                   check=True, env=env)
    after = os.times()
    return (after.children_user - before.children_user) + (after.children_system - before.children_system)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a", default="/work/main/build/penumbra", help="build A's penumbra")
    parser.add_argument("--a-untextured-only", action="store_true", help="build A cannot render textures")
    parser.add_argument("--b", default=os.path.join(ROOT, "build", "penumbra"), help="build B's penumbra")
    parser.add_argument("--rounds", type=int, default=9)
    args = parser.parse_args()
    env = dict(os.environ)
    icds = glob.glob("/usr/share/vulkan/icd.d/lvp_icd*.json")
    if icds:
        env.update(VK_ICD_FILENAMES=icds[0], VK_DRIVER_FILES=icds[0])
    with tempfile.TemporaryDirectory() as tmp:
        with open(os.path.join(ROOT, "scenes", "cornell.json")) as f:
            scene = json.load(f)
        plain = os.path.join(tmp, "plain.json")
        with open(plain, "w") as f:
            json.dump(scene, f)
        noise_png(os.path.join(tmp, "noise.png"))
        for m in scene["materials"].values():
            m["albedo"] = {"texture": "noise.png", "scale": m["albedo"]}
        textured = os.path.join(tmp, "textured.json")
        with open(textured, "w") as f:
            json.dump(scene, f)
        out = os.path.join(tmp, "out.exr")
        configs = [("A, untextured", args.a, plain), ("B, untextured", args.b, plain)]
        if not args.a_untextured_only:
            configs.append(("A, textured", args.a, textured))
        configs.append(("B, textured", args.b, textured))
        results = {name: [] for name, _, _ in configs}
        for _ in range(args.rounds):
            for name, exe, path in configs:
                results[name].append(cpu_seconds(exe, path, 68, out, env) - cpu_seconds(exe, path, 4, out, env))
    base = results["A, untextured"]
    for name, values in results.items():
        ratio = statistics.median(v / b for v, b in zip(values, base))
        print(f"{name}: {statistics.median(values):.2f} CPU s per 64 spp; per-round ratio to A: median {ratio:.3f}")
    if "A, textured" in results:
        # The texture paths against each other: B textured / A textured, round by round.
        ratio = statistics.median(b / a for a, b in zip(results["A, textured"], results["B, textured"]))
        print(f"B textured / A textured, per round: median {ratio:.3f}")
    with open("/proc/loadavg") as f:
        print("load average:", " ".join(f.read().split()[:3]))


if __name__ == "__main__":
    main()
