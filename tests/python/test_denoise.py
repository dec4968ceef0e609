# penumbra.denoise (python/penumbra/denoise.py): Open Image Denoise through pyoidn. Run by
# tests/python/run_denoise_test with build/venv-denoise's Python, which has pyoidn.
import sys

import numpy as np
import pytest

import penumbra

# The Cornell box at its own 400x400 (a 1024-spp reference takes ~15 s on lavapipe): at
# 64x64 the filter's blur of the walls' edges costs about as much as the noise it removes.
SIZE = dict(width=400, height=400)
NOISY_SPP = 4
REFERENCE_SPP = 1024


def relmse(a, b):
    """Mean of (a-b)^2 / (b^2 + 1e-2) over pixels and channels (docs/figures/README.md)."""
    return float(np.mean((a - b) ** 2 / (b * b + 1e-2)))


@pytest.fixture(scope="module")
def cornell_images(request):
    from conftest import CORNELL

    noisy = penumbra.render(CORNELL, spp=NOISY_SPP, seed=1, aovs=["albedo", "normal"], **SIZE)
    # Another seed: the reference's error is independent of the noisy image's.
    reference = penumbra.render(CORNELL, spp=REFERENCE_SPP, seed=2, **SIZE)["rgb"]
    return noisy, reference


@pytest.mark.parametrize("aux", [(), ("albedo",), ("albedo", "normal")])
def test_denoised_cornell_is_closer_to_the_reference(cornell_images, aux):
    noisy, reference = cornell_images
    denoised = penumbra.denoise(noisy["rgb"], **{name: noisy[name] for name in aux})
    before, after = relmse(noisy["rgb"], reference), relmse(denoised, reference)
    # Measured: noisy 0.00098, denoised 0.00020 / 0.00027 / 0.00020 (none / albedo /
    # albedo+normal), factors 4.96 / 3.59 / 4.85; over seeds 1, 3, 5 the factors ranged
    # 2.9 to 5.0. The reference's own error (1024 spp) is ~1/256 of the noisy image's.
    assert after * 2 < before, (before, after)


@pytest.mark.parametrize("value", [0.5, 3.0])
def test_constant_image_stays_nearly_constant(value):
    out = penumbra.denoise(np.full((64, 64, 3), value, np.float32))
    change = np.abs(out / value - 1)
    # Measured for both values: mean 0.0011, 99th percentile 0.0081, at most 0.026 inside
    # a 2-pixel border and 0.046 in a corner (OIDN's borders are not exact).
    assert change.mean() < 0.002 and np.percentile(change, 99) < 0.015 and change[2:-2, 2:-2].max() < 0.05


def test_shapes_and_dtypes():
    rgb = np.random.default_rng(3).random((10, 17, 3))  # float64, converted
    out = penumbra.denoise(rgb)
    assert out.dtype == np.float32 and out.shape == (10, 17, 3) and np.isfinite(out).all()
    # A non-contiguous view is taken as its values.
    wide = np.random.default_rng(4).random((10, 34, 3)).astype(np.float32)
    np.testing.assert_array_equal(penumbra.denoise(wide[:, ::2]), penumbra.denoise(wide[:, ::2].copy()))
    assert penumbra.denoise(rgb, albedo=rgb, normal=rgb * 2 - 1).shape == (10, 17, 3)


@pytest.mark.parametrize(
    "args, kwargs, message",
    [
        ((np.zeros((4, 4, 3)),), dict(normal=np.zeros((4, 4, 3))), "normal needs albedo"),
        ((np.zeros((4, 4)),), {}, r"rgb has shape \(4, 4\)"),
        ((np.zeros((4, 4, 4)),), {}, r"rgb has shape \(4, 4, 4\)"),
        ((np.zeros((0, 4, 3)),), {}, r"rgb has shape \(0, 4, 3\)"),
        ((np.zeros((4, 4, 3)),), dict(albedo=np.zeros((4, 5, 3))), r"albedo has shape \(4, 5, 3\), rgb has"),
        ((np.full((4, 4, 3), np.nan),), {}, "rgb has NaN or infinite"),
        ((np.zeros((4, 4, 3)),), dict(albedo=np.full((4, 4, 3), np.inf)), "albedo has NaN or infinite"),
        ((["a"],), {}, "rgb must be a float array"),
    ],
)
def test_bad_arguments_raise_one_line(args, kwargs, message):
    with pytest.raises(ValueError, match=message) as caught:
        penumbra.denoise(*args, **kwargs)
    assert "\n" not in str(caught.value)


def test_without_pyoidn_the_error_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "pyoidn", None)  # import pyoidn then raises ImportError
    with pytest.raises(ImportError) as caught:
        penumbra.denoise(np.zeros((4, 4, 3)))
    message = str(caught.value)
    assert message.startswith("penumbra.denoise needs pyoidn: pip install penumbra[denoise]") and "\n" not in message


# `penumbra render --denoise` (host/cli/denoise_step.h, python/penumbra/denoise_exr.py): the
# program runs $PENUMBRA_PYTHON -m penumbra.denoise_exr (run_denoise_test sets it to the venv's).
SMALL_CLI = ["--spp", "4", "--seed", "3", "--width", "40", "--height", "30", "--quiet"]


def run_cli(*args, env=None):
    import os
    import subprocess

    from conftest import SOURCE_DIR

    exe = os.environ.get("PENUMBRA_EXECUTABLE", str(SOURCE_DIR / "build" / "penumbra"))
    full_env = dict(os.environ, **(env or {}))
    return subprocess.run([exe, *map(str, args)], capture_output=True, text=True, timeout=600, env=full_env)


@pytest.mark.parametrize("aovs", [[], ["albedo"], ["albedo", "normal"]])
def test_cli_denoise_adds_the_denoised_layer(cornell, tmp_path, aovs):
    aov_args = ["--aov", ",".join(aovs)] if aovs else []
    plain, denoised = tmp_path / "plain.exr", tmp_path / "denoised.exr"
    done = run_cli("render", cornell, *SMALL_CLI, *aov_args, "-o", plain)
    assert done.returncode == 0, done.stderr
    done = run_cli("render", cornell, *SMALL_CLI, *aov_args, "--denoise", "-o", denoised)
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["denoised.exr", "plain.exr"]  # no temporary left
    noisy, out = penumbra.read_exr(plain), penumbra.read_exr(denoised)
    assert list(out) == ["rgb", *aovs, "denoised"]  # penumbra:aovs names it, after the scene's
    for name in noisy:  # the noisy image and its layers stay as they were
        np.testing.assert_array_equal(out[name], noisy[name])
    expected = penumbra.denoise(noisy["rgb"], **{name: noisy[name] for name in aovs})
    np.testing.assert_allclose(out["denoised"], expected, rtol=1e-6, atol=1e-7)
    assert np.abs(out["denoised"] - noisy["rgb"]).max() > 0.01  # filtered, not a copy


def test_cli_without_the_denoiser_exits_2_before_rendering(cornell, tmp_path):
    import os

    # A pyoidn that fails to import, first on the path: as if it were not installed.
    (tmp_path / "fake" / "pyoidn").mkdir(parents=True)
    (tmp_path / "fake" / "pyoidn" / "__init__.py").write_text("raise ImportError(\"No module named 'pyoidn'\")\n")
    path = f"{tmp_path / 'fake'}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"
    out = tmp_path / "out.exr"
    done = run_cli("render", cornell, *SMALL_CLI, "--denoise", "-o", out, env={"PYTHONPATH": path, "PENUMBRA_PHASES": "1"})
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert lines[0].startswith("penumbra: phase load ") and lines[1:] == [
        "penumbra: --denoise: penumbra.denoise needs pyoidn: pip install penumbra[denoise] (or pip install pyoidn) "
        "(No module named 'pyoidn')"
    ], lines  # one line, and no phase after loading the scene: no device opened, no render
    done = run_cli("render", cornell, *SMALL_CLI, "--denoise", "-o", out, env={"PENUMBRA_PYTHON": str(tmp_path / "none")})
    assert done.returncode == 2 and done.stderr.count("\n") == 1
    assert f"--denoise: no {tmp_path / 'none'} to run the denoiser" in done.stderr
    done = run_cli("render", cornell, *SMALL_CLI, "--denoise", "-o", tmp_path / "out.png")
    assert done.returncode == 2 and "--denoise adds a layer to an EXR" in done.stderr
    assert list(tmp_path.glob("out.*")) == []


def test_cli_denoiser_failing_after_the_render_leaves_nothing(cornell, tmp_path):
    # An interpreter that passes the check and then fails: the render is lost, not half-written.
    fake = tmp_path / "python"
    fake.write_text('#!/bin/sh\n[ "$3" = --check ] && exit 0\necho "Traceback ..." >&2\necho "boom" >&2\nexit 1\n')
    fake.chmod(0o755)
    (tmp_path / "out").mkdir()
    done = run_cli("render", cornell, *SMALL_CLI, "--denoise", "-o", tmp_path / "out" / "x.exr",
                   env={"PENUMBRA_PYTHON": str(fake)})
    assert done.returncode == 1
    assert done.stderr.strip() == f"penumbra: --denoise: {tmp_path / 'out' / 'x.exr'} not written: boom"
    assert list((tmp_path / "out").iterdir()) == []


def test_scenes_cannot_ask_for_denoised(cornell, tmp_path):
    done = run_cli("render", cornell, *SMALL_CLI, "--aov", "denoised", "-o", tmp_path / "x.exr")
    assert done.returncode == 2 and "film.aovs[0]" in done.stderr


def test_merge_averages_denoised_layers_by_spp(cornell, tmp_path):
    # docs/SCENE_FORMAT.md "Denoising": merge carries the layer, weighted as albedo is.
    parts = []
    for offset, spp in ((0, 2), (2, 6)):
        part = tmp_path / f"part{offset}.exr"
        args = ["--spp", spp, "--set", f"sampler.sample_offset={offset}", "--width", 24, "--height", 16, "--quiet"]
        done = run_cli("render", cornell, *args, "--denoise", "-o", part)
        assert done.returncode == 0, done.stderr
        parts.append(penumbra.read_exr(part)["denoised"])
    done = run_cli("merge", tmp_path / "part0.exr", tmp_path / "part2.exr", "-o", tmp_path / "merged.exr")
    assert done.returncode == 0, done.stderr
    merged = penumbra.read_exr(tmp_path / "merged.exr")
    assert list(merged) == ["rgb", "denoised"]
    np.testing.assert_allclose(merged["denoised"], (2 * parts[0] + 6 * parts[1]) / 8, rtol=1e-6, atol=1e-7)


def test_denoise_exr_refuses_a_bad_file_in_one_line(tmp_path):
    import subprocess

    bad = tmp_path / "bad.exr"
    bad.write_text("not an EXR")
    done = subprocess.run([sys.executable, "-m", "penumbra.denoise_exr", str(bad), str(tmp_path / "out.exr")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and str(bad) in done.stderr
    assert not (tmp_path / "out.exr").exists()
    done = subprocess.run([sys.executable, "-m", "penumbra.denoise_exr"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and done.stderr.startswith("usage:")
