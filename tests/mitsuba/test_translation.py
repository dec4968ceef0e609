"""Every scene in scenes/ through tools/mitsuba_penumbra.py: Mitsuba 3 (llvm_ad_rgb) and Penumbra
render it at the same tiny size, and their per-channel image means must agree within
Z standard errors of the difference (paired_z), and so must each quadrant's. Scenes of tests/mitsuba/scenes cover what scenes/ lacks. Then a
deliberate mutation (the pbr dielectric f0 0.04 -> 0.08, on tests/mitsuba/scenes/
pbr_dielectric.json) must fail the same check, so the test has the power to see a wrong translation.

Usage: python test_translation.py PENUMBRA_EXECUTABLE SOURCE_DIR. Exit 77 (CTest's SKIP) when
mitsuba is not importable: run tools/setup to create build/venv-mitsuba."""
import glob
import json
import os
import subprocess
import sys
import tempfile

try:
    import numpy as np
    import mitsuba as mi
except ImportError as e:
    print(f"SKIPPED: mitsuba or numpy not importable ({e}); tools/setup creates build/venv-mitsuba")
    sys.exit(77)

W, H, BLOCK = 48, 32, 4
SPP = {"penumbra": 256, "mitsuba": 256}
# A 4.5-sigma band: 7e-6 per comparison by chance, under 0.2% for the test's
# 10 scenes x 5 regions x 3 channels.
Z = 4.5


def paired_z(a, b):
    """|mean(a - b)| / its standard error, per channel. The error is estimated from the means
    of the difference image over BLOCK x BLOCK pixel blocks: where the two renderers agree the
    image's structure cancels in a - b, so the blocks' spread is the two renders' noise
    (independent seeds); a local disagreement only adds to the spread (a wider band, no
    false failure)."""
    h, w = a.shape[0] // BLOCK, a.shape[1] // BLOCK
    d = (a - b)[: h * BLOCK, : w * BLOCK]
    blocks = d.reshape(h, BLOCK, w, BLOCK, 3).mean(axis=(1, 3)).reshape(-1, 3)
    se = blocks.std(axis=0, ddof=1) / np.sqrt(len(blocks))
    return np.abs(blocks.mean(axis=0)) / np.maximum(se, 1e-12)


def render_penumbra(exe, scene_path, out):
    subprocess.run([exe, "render", scene_path, "--quiet", "--width", str(W), "--height", str(H),
                    "--spp", str(SPP["penumbra"]), "--seed", "1", "-o", out], check=True)
    bmp = mi.Bitmap(out)
    return np.array(bmp, dtype=np.float64)[:, :, :3]


def render_mitsuba(mp, scene_path):
    with open(scene_path) as f:
        scene = json.load(f)
    scene.setdefault("film", {}).update(width=W, height=H)
    d = mp.translate(scene, spp=SPP["mitsuba"], seed=2, base_dir=os.path.dirname(scene_path))
    return np.array(mi.render(mi.load_dict(d)), dtype=np.float64)[:, :, :3]


def agree(a, b):
    """The whole image's means and each quadrant's (a moved or mis-oriented object can keep
    the whole image's mean): all within Z standard errors."""
    h, w = H // 2, W // 2
    parts = [(a, b)] + [(a[i:i + h, j:j + w], b[i:i + h, j:j + w]) for i in (0, h) for j in (0, w)]
    z = np.array([paired_z(pa, pb) for pa, pb in parts])
    return bool(np.all(z <= Z)), a.mean(axis=(0, 1)), b.mean(axis=(0, 1)), z.max(axis=0)


def main():
    exe, src = sys.argv[1], sys.argv[2]
    # llvm_ad_rgb: Mitsuba's scalar variants crash in Python integrators (penumbra_ao).
    try:
        mi.set_variant("llvm_ad_rgb")
    except Exception as e:  # no libLLVM (DRJIT_LIBLLVM_PATH): a missing dependency, not a pass
        print(f"SKIPPED: Mitsuba's llvm_ad_rgb variant is unavailable ({e}); tools/setup installs libllvm19")
        sys.exit(77)
    sys.path.insert(0, os.path.join(src, "tools"))
    import mitsuba_penumbra as mp
    import penumbra_tools.mitsuba_pbr as pbr
    failures = []
    penumbra_images = {}
    with tempfile.TemporaryDirectory() as tmp:
        # Every scene of scenes/, and those of tests/mitsuba/scenes for what scenes/ lacks.
        for path in sorted(glob.glob(os.path.join(src, "scenes", "*.json"))) + \
                sorted(glob.glob(os.path.join(src, "tests", "mitsuba", "scenes", "*.json"))):
            name = os.path.basename(path)
            a = render_penumbra(exe, path, os.path.join(tmp, name + ".exr"))
            b = render_mitsuba(mp, path)
            penumbra_images[name] = a
            ok, ma, mb, z = agree(a, b)
            print(f"{'ok  ' if ok else 'FAIL'} {name}: penumbra {np.round(ma, 4)} mitsuba {np.round(mb, 4)} "
                  f"max |z| {np.round(z, 2)}", flush=True)
            if not ok:
                failures.append(name)
        # The mutation: the test must see a wrong dielectric Fresnel f0 (0.04 -> 0.08) in the
        # pbr translation, on the low-noise pbr scene of tests/mitsuba/scenes.
        mutated_scene = "pbr_dielectric.json"
        pbr.DIELECTRIC_F0, saved = 0.08, pbr.DIELECTRIC_F0
        try:
            b = render_mitsuba(mp, os.path.join(src, "tests", "mitsuba", "scenes", mutated_scene))
        finally:
            pbr.DIELECTRIC_F0 = saved
        ok, ma, mb, z = agree(penumbra_images[mutated_scene], b)
        print(f"{'FAIL' if ok else 'ok  '} mutation f0 0.08 on {mutated_scene} "
              f"{'passed (the test cannot see it)' if ok else 'rejected'}: |z| {np.round(z, 2)}", flush=True)
        if ok:
            failures.append("mutation")
    if failures:
        print("failed: " + ", ".join(failures))
        sys.exit(1)


if __name__ == "__main__":
    main()
