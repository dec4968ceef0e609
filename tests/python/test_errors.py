# Bad input raises penumbra.SceneError (a ValueError) whose message is the command line's
# one-line message (without its "penumbra: " prefix); other failures RenderError.
import json
import math

import pytest

import penumbra


def cli_message(done):
    assert done.returncode in (1, 2), (done.returncode, done.stderr)
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("penumbra: "), done.stderr
    return lines[0][len("penumbra: "):]


def bad_scene(cornell):
    scene = json.loads(cornell.read_text())
    scene["shapes"][3]["material"] = "flor"
    return scene


def test_scene_file_error_is_the_cli_message(cornell, cli, tmp_path):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(bad_scene(cornell)))
    message = cli_message(cli("render", path, "-o", tmp_path / "x.exr"))
    with pytest.raises(penumbra.SceneError) as caught:
        penumbra.render(path)
    assert str(caught.value) == message
    assert 'shapes[3].material: unknown material "flor"' in message
    assert isinstance(caught.value, ValueError)
    with pytest.raises(penumbra.SceneError, match="^" + message.replace("[", r"\[").replace("]", r"\]")):
        penumbra.Renderer(str(path))


def test_dict_error_names_the_dict(cornell, cli, tmp_path):
    """A dict scene's messages say <dict> where a file's name would stand."""
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(bad_scene(cornell)))
    message = cli_message(cli("render", path, "-o", tmp_path / "x.exr"))
    with pytest.raises(penumbra.SceneError) as caught:
        penumbra.render(bad_scene(cornell))
    assert str(caught.value) == message.replace(str(path), "<dict>", 1)


@pytest.mark.parametrize("path, value, cli_value", [
    ("sampler.spp", -1, "-1"),
    ("camera.fov_y", 200, "200"),
    ("integrator.strategy", "bsdff", "bsdff"),
    ("lights[5].power", 1, "1"),
    ("camera..eye", 1, "1"),
])
def test_set_errors_are_the_cli_messages(cornell, cli, tmp_path, path, value, cli_value):
    message = cli_message(cli("render", cornell, "--set", f"{path}={cli_value}", "-o", tmp_path / "x.exr"))
    with pytest.raises(penumbra.SceneError) as caught:
        penumbra.render(cornell, set={path: value})
    assert str(caught.value) == message


def test_shorthand_error_is_the_cli_message(cornell, cli, tmp_path):
    message = cli_message(cli("render", cornell, "--width", 0, "-o", tmp_path / "x.exr"))
    with pytest.raises(penumbra.SceneError) as caught:
        penumbra.render(cornell, width=0)
    assert str(caught.value) == message


def test_missing_file_is_the_cli_message(cli, tmp_path):
    missing = tmp_path / "missing.json"
    message = cli_message(cli("render", missing, "-o", tmp_path / "x.exr"))
    with pytest.raises(penumbra.SceneError) as caught:
        penumbra.render(missing)
    assert str(caught.value) == message


def test_not_finite_in_a_dict_is_refused_at_its_path(cornell):
    scene = json.loads(cornell.read_text())
    scene["camera"]["eye"][1] = math.nan
    with pytest.raises(penumbra.SceneError, match=r"^<dict>: camera\.eye\[1\]: .*finite"):
        penumbra.render(scene)
    with pytest.raises(penumbra.SceneError, match=r"camera\.eye\[0\]: .*finite"):
        penumbra.render(cornell, set={"camera.eye": [math.inf, 1, 4]})


def test_values_that_are_not_json(cornell):
    with pytest.raises(penumbra.SceneError, match=r"^<dict>: camera\.eye: a Python set is not a JSON value"):
        penumbra.render({"camera": {"eye": {1, 2, 3}}})
    with pytest.raises(TypeError):
        penumbra.render(42)


def test_no_such_device_is_a_render_error(cornell, cli, tmp_path):
    message = cli_message(cli("render", cornell, "--device", 99, "--spp", 1, "-o", tmp_path / "x.exr"))
    with pytest.raises(penumbra.RenderError) as caught:
        penumbra.render(cornell, spp=1, device=99)
    assert str(caught.value) == message
    assert not isinstance(caught.value, ValueError)


def test_unreadable_exr_is_a_scene_error(tmp_path, cli):
    bad = tmp_path / "bad.exr"
    bad.write_bytes(b"not an exr")
    message = cli_message(cli("compare", bad, bad))
    with pytest.raises(penumbra.SceneError) as caught:
        penumbra.read_exr(bad)
    assert str(caught.value) == message
