"""Every scene in scenes/ through tools/penumbra_tools/mitsuba_penumbra.py: Mitsuba 3 (llvm_ad_rgb) and Penumbra
render it at the same tiny size, and their per-channel image means must agree within
Z standard errors (paired_z: each renderer renders twice, the noise is estimated from the
difference of its two renders), and so must each quadrant's. Scenes of tests/mitsuba/scenes cover what scenes/ lacks. Then a
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


def region_stats(pair):
    """Mean of the average of two renders (independent seeds) and its standard error, per
    channel. The error comes from the means of their difference over BLOCK x BLOCK pixel
    blocks: the image's structure cancels exactly in the difference of two renders of the
    same renderer, so the blocks' spread is the renders' noise alone
    (var((X1 + X2) / 2) = var(X1 - X2) / 4)."""
    x1, x2 = pair
    h, w = x1.shape[0] // BLOCK, x1.shape[1] // BLOCK
    d = (x1 - x2)[: h * BLOCK, : w * BLOCK]
    blocks = d.reshape(h, BLOCK, w, BLOCK, 3).mean(axis=(1, 3)).reshape(-1, 3)
    se = blocks.std(axis=0, ddof=1) / (2.0 * np.sqrt(len(blocks)))
    return (0.5 * (x1 + x2)).mean(axis=(0, 1)), se


def paired_z(a, b):
    """|mean(A) - mean(B)| / its standard error, per channel; a and b are pairs of renders."""
    (ma, sa), (mb, sb) = region_stats(a), region_stats(b)
    return np.abs(ma - mb) / np.maximum(np.sqrt(sa * sa + sb * sb), 1e-12)


def render_penumbra(exe, scene_path, out):
    """Two renders with seeds 1 and 2."""
    images = []
    for seed in (1, 2):
        subprocess.run([exe, "render", scene_path, "--quiet", "--width", str(W), "--height", str(H),
                        "--spp", str(SPP["penumbra"]), "--seed", str(seed), "-o", out], check=True)
        images.append(np.array(mi.Bitmap(out), dtype=np.float64)[:, :, :3])
    return images


def render_mitsuba(mp, scene_path):
    """Two renders with seeds 3 and 4."""
    with open(scene_path) as f:
        scene = json.load(f)
    scene.setdefault("film", {}).update(width=W, height=H)
    d = mi.load_dict(mp.translate(scene, spp=SPP["mitsuba"], seed=0, base_dir=os.path.dirname(scene_path)))
    return [np.array(mi.render(d, seed=seed), dtype=np.float64)[:, :, :3] for seed in (3, 4)]


def agree(a, b):
    """The whole image's means and each quadrant's (a moved or mis-oriented object can keep
    the whole image's mean): all within Z standard errors. a, b: pairs of renders."""
    h, w = H // 2, W // 2
    parts = [(a, b)] + [([x[i:i + h, j:j + w] for x in a], [x[i:i + h, j:j + w] for x in b])
                        for i in (0, h) for j in (0, w)]
    z = np.array([paired_z(pa, pb) for pa, pb in parts])
    mean = lambda pair: (0.5 * (pair[0] + pair[1])).mean(axis=(0, 1))  # noqa: E731
    return bool(np.all(z <= Z)), mean(a), mean(b), z.max(axis=0)


def main():
    exe, src = sys.argv[1], sys.argv[2]
    # llvm_ad_rgb: Mitsuba's scalar variants crash in Python integrators (penumbra_ao).
    try:
        mi.set_variant("llvm_ad_rgb")
    except Exception as e:  # no libLLVM (DRJIT_LIBLLVM_PATH): a missing dependency, not a pass
        print(f"SKIPPED: Mitsuba's llvm_ad_rgb variant is unavailable ({e}); tools/setup installs libllvm19")
        sys.exit(77)
    sys.path.insert(0, os.path.join(src, "tools"))
    from penumbra_tools import mitsuba_penumbra as mp
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
