# penumbra.render and the EXR functions: shapes and dtypes, the same pixels and header as
# `penumbra render`, dict scenes, and write_exr / read_exr.
import json

import numpy as np
import pytest

import penumbra

SMALL = dict(width=24, height=16, spp=2, seed=3)


def test_shapes_dtypes_and_meta(cornell):
    img = penumbra.render(cornell, **SMALL)
    assert isinstance(img, penumbra.Layers) and list(img) == ["rgb"]
    rgb = img["rgb"]
    assert rgb.dtype == np.float32 and rgb.shape == (16, 24, 3) and rgb.flags.c_contiguous
    assert np.isfinite(rgb).all() and rgb.mean() > 0.01  # lit, not black
    assert img.meta["spp"] == 2 and img.meta["seed"] == 3 and img.meta["sample_offset"] == 0
    assert json.loads(img.meta["integrator"])["type"] == "direct"
    assert img.meta["render_seconds"] >= 0


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float32).view(np.uint32)


def test_equals_cli_bit_for_bit(cornell, cli, tmp_path):
    out = tmp_path / "cli.exr"
    done = cli("render", cornell, "--spp", 3, "--seed", 5, "--width", 32, "--height", 24, "--quiet", "-o", out)
    assert done.returncode == 0, done.stderr
    ours = penumbra.render(cornell, spp=3, seed=5, width=32, height=24)
    theirs = penumbra.read_exr(out)
    np.testing.assert_array_equal(bits(ours["rgb"]), bits(theirs["rgb"]))
    for meta in (ours.meta, theirs.meta):
        meta.pop("render_seconds")
    assert ours.meta == theirs.meta


def test_write_exr_writes_the_cli_file(cornell, cli, tmp_path):
    """With the CLI's render_seconds (wall time, the one attribute that differs), write_exr
    writes the CLI's file byte for byte: same channels, attributes and compression."""
    out = tmp_path / "cli.exr"
    done = cli("render", cornell, "--spp", 2, "--seed", 1, "--width", 16, "--height", 16, "--quiet", "-o", out)
    assert done.returncode == 0, done.stderr
    img = penumbra.render(cornell, spp=2, seed=1, width=16, height=16)
    img.meta["render_seconds"] = penumbra.read_exr(out).meta["render_seconds"]
    penumbra.write_exr(tmp_path / "ours.exr", img)
    assert (tmp_path / "ours.exr").read_bytes() == out.read_bytes()


def test_dict_scene_equals_file(cornell):
    scene = json.loads(cornell.read_text())
    from_dict = penumbra.render(scene, **SMALL)
    from_file = penumbra.render(str(cornell), **SMALL)
    np.testing.assert_array_equal(bits(from_dict["rgb"]), bits(from_file["rgb"]))


def test_set_and_shorthands_as_on_the_command_line(cornell, cli, tmp_path):
    """set= values are JSON values (numpy arrays too); spp= wins over set's sampler.spp,
    as --spp over --set."""
    out = tmp_path / "cli.exr"
    done = cli("render", cornell, "--set", "camera.eye=[0.5,1,3.5]", "--set", "sampler.spp=9", "--set",
               "integrator.strategy=bsdf", "--spp", 2, "--width", 16, "--height", 12, "--quiet", "-o", out)
    assert done.returncode == 0, done.stderr
    ours = penumbra.render(cornell, spp=2, width=16, height=12,
                           set={"camera.eye": np.array([0.5, 1, 3.5]), "sampler.spp": 9,
                                "integrator.strategy": "bsdf"})
    assert ours.meta["spp"] == 2
    np.testing.assert_array_equal(bits(ours["rgb"]), bits(penumbra.read_exr(out)["rgb"]))


def test_write_read_round_trip(tmp_path):
    rng = np.random.default_rng(7)
    img = penumbra.Layers({"rgb": rng.random((5, 7, 3), dtype=np.float32) * 100},
                          meta={"spp": 12, "seed": 4, "sample_offset": 8, "integrator": '{"type":"ao"}',
                                "render_seconds": 1.25, "sampler": "sobol", "pieces": "4:8-20"})
    penumbra.write_exr(tmp_path / "x.exr", img)
    back = penumbra.read_exr(tmp_path / "x.exr")
    np.testing.assert_array_equal(bits(back["rgb"]), bits(img["rgb"]))
    assert back.meta == img.meta
    # A plain dict without meta writes a file without penumbra attributes.
    penumbra.write_exr(tmp_path / "plain.exr", {"rgb": img["rgb"].astype(np.float64)})
    plain = penumbra.read_exr(tmp_path / "plain.exr")
    np.testing.assert_array_equal(plain["rgb"], img["rgb"])
    assert plain.meta == {}


def test_write_exr_refuses_unknown_layers(tmp_path):
    rgb = np.zeros((2, 2, 3), np.float32)
    with pytest.raises(ValueError, match='unknown layer "dpeth"'):
        penumbra.write_exr(tmp_path / "x.exr", {"rgb": rgb, "dpeth": rgb[..., 0]})
    with pytest.raises(ValueError, match=r"shape \(height, width, 3\)"):
        penumbra.write_exr(tmp_path / "x.exr", {"rgb": rgb[..., :2]})
    assert not (tmp_path / "x.exr").exists()


def test_devices():
    devices = penumbra.devices()
    assert devices and sum(d["chosen"] for d in devices) == 1
    assert {"index", "name", "type", "vulkan", "driver"} <= set(devices[0])


def test_write_png_writes_the_cli_png(cornell, cli, tmp_path):
    """write_png encodes as `penumbra render --png` does (same pixels, same bytes)."""
    done = cli("render", cornell, "--spp", 2, "--seed", 1, "--width", 16, "--height", 12, "--quiet",
               "-o", tmp_path / "cli.exr", "--png", tmp_path / "cli.png")
    assert done.returncode == 0, done.stderr
    penumbra.write_png(tmp_path / "ours.png", penumbra.read_exr(tmp_path / "cli.exr"))
    assert (tmp_path / "ours.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    penumbra.write_png(tmp_path / "brighter.png", penumbra.read_exr(tmp_path / "cli.exr"), exposure=1)
    assert (tmp_path / "brighter.png").read_bytes() != (tmp_path / "cli.png").read_bytes()
