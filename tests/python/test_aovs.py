# AOV layers through the module (docs/SCENE_FORMAT.md "AOVs (v3)", "Python (v3)"): aovs= in
# render and Renderer.render, names checked with the CLI's message, numpy layers of the
# documented dtypes and shapes, and read_exr / write_exr round-tripping the CLI's EXR.
import numpy as np
import pytest

import penumbra

from test_errors import cli_message

ALL = ["albedo", "normal", "position", "depth", "shape_id", "primitive_id", "material_id", "variance"]
SMALL = dict(width=20, height=14, spp=3, seed=2)


def test_layers_have_the_documented_dtypes_and_shapes(cornell):
    img = penumbra.render(cornell, aovs=ALL, **SMALL)
    assert list(img) == ["rgb"] + ALL  # film.aovs' order, after rgb
    for name in ALL:
        layer = img[name]
        if name.endswith("_id"):
            assert layer.dtype == np.uint32 and layer.shape == (14, 20), name
        elif name == "depth":
            assert layer.dtype == np.float32 and layer.shape == (14, 20), name
        else:
            assert layer.dtype == np.float32 and layer.shape == (14, 20, 3), name
    # The box fills most of the film (the wider film sees past its sides): layers of hits.
    hit = img["shape_id"] != 0xFFFFFFFF
    assert hit.mean() > 0.5 and np.isfinite(img["depth"]).mean() > 0.5
    # Means of unit normals: at most 1 long, and 1 inside a wall (most pixels).
    lengths = np.linalg.norm(img["normal"], axis=2)
    assert (lengths <= 1 + 1e-5).all() and np.median(lengths[hit]) > 0.999


def test_renderer_takes_aovs_per_render(cornell):
    r = penumbra.Renderer(cornell, **SMALL)
    assert list(r.render()) == ["rgb"]
    with_depth = r.render(aovs=["depth"])
    assert list(with_depth) == ["rgb", "depth"]
    # The AOVs' kernel computes the same image: the layers add, they do not change it.
    np.testing.assert_array_equal(with_depth["rgb"], r.render()["rgb"])


@pytest.mark.parametrize("aovs, cli_value", [(["depth", "bogus"], "depth,bogus"), (["depth", "depth"], "depth,depth")])
def test_bad_names_raise_the_cli_message(cornell, cli, tmp_path, aovs, cli_value):
    message = cli_message(cli("render", cornell, "--aov", cli_value, "-o", tmp_path / "x.exr"))
    assert "film.aovs[1]" in message
    with pytest.raises(penumbra.SceneError) as caught:
        penumbra.render(cornell, aovs=aovs)
    assert str(caught.value) == message
    r = penumbra.Renderer(cornell, **SMALL)
    with pytest.raises(penumbra.SceneError) as caught:
        r.render(aovs=aovs)
    assert str(caught.value) == message
    with pytest.raises(TypeError, match="list of layer names"):
        penumbra.render(cornell, aovs="depth")


def bits(a):
    """Exact comparison of float layers (+inf depth and -0 included)."""
    return np.ascontiguousarray(a).view(np.uint32)


def cli_render(cli, cornell, out):
    done = cli("render", cornell, "--spp", 3, "--seed", 2, "--width", 20, "--height", 14, "--aov", ",".join(ALL),
               "--quiet", "-o", out)
    assert done.returncode == 0, done.stderr


def test_read_exr_of_the_cli_file_equals_the_render(cornell, cli, tmp_path):
    cli_render(cli, cornell, tmp_path / "cli.exr")
    theirs = penumbra.read_exr(tmp_path / "cli.exr")
    ours = penumbra.render(cornell, aovs=ALL, **SMALL)
    assert list(theirs) == list(ours)
    for name in ours:
        assert theirs[name].dtype == ours[name].dtype and theirs[name].shape == ours[name].shape, name
        np.testing.assert_array_equal(bits(theirs[name]), bits(ours[name]), err_msg=name)


def test_write_exr_of_the_render_is_the_cli_file(cornell, cli, tmp_path):
    """Channel by channel, and with the CLI's render_seconds byte for byte."""
    cli_render(cli, cornell, tmp_path / "cli.exr")
    img = penumbra.render(cornell, aovs=ALL, **SMALL)
    img.meta["render_seconds"] = penumbra.read_exr(tmp_path / "cli.exr").meta["render_seconds"]
    penumbra.write_exr(tmp_path / "ours.exr", img)
    assert (tmp_path / "ours.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    back = penumbra.read_exr(tmp_path / "ours.exr")
    for name in img:
        np.testing.assert_array_equal(bits(back[name]), bits(img[name]), err_msg=name)


def test_write_exr_checks_the_layers(tmp_path):
    rgb = np.zeros((4, 5, 3), np.float32)
    for layers, match in [({"rgb": rgb, "depht": np.zeros((4, 5))}, 'unknown layer "depht"'),
                          ({"rgb": rgb, "depth": np.zeros((4, 5, 3))}, r'layers\["depth"\] must be an array of shape \(4, 5\)'),
                          ({"rgb": rgb, "normal": np.zeros((4, 5))}, r"shape \(4, 5, 3\)"),
                          ({"rgb": rgb, "shape_id": np.zeros((4, 5), np.float32)}, "unsigned integer")]:
        with pytest.raises(ValueError, match=match):
            penumbra.write_exr(tmp_path / "x.exr", penumbra.Layers(layers))
        assert not (tmp_path / "x.exr").exists()


def test_opens_in_python_openexr(cornell, cli, tmp_path):
    """The channel names of the contract, read by OpenEXR's own Python binding."""
    OpenEXR = pytest.importorskip("OpenEXR", reason="OpenEXR's Python binding is not installed")
    cli_render(cli, cornell, tmp_path / "cli.exr")
    ours = penumbra.read_exr(tmp_path / "cli.exr")
    channels = {"albedo": "RGB", "normal": "XYZ", "position": "XYZ", "variance": "RGB"}
    with OpenEXR.File(str(tmp_path / "cli.exr"), separate_channels=True) as f:
        found = f.channels()
        for name, suffixes in channels.items():
            for c, s in enumerate(suffixes):
                np.testing.assert_array_equal(found[f"{name}.{s}"].pixels, ours[name][:, :, c], err_msg=name)
        np.testing.assert_array_equal(found["depth.Z"].pixels, ours["depth"])
        for name in ("shape_id", "primitive_id", "material_id"):
            assert found[name].pixels.dtype == np.uint32
            np.testing.assert_array_equal(found[name].pixels, ours[name])
