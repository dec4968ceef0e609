# The benchmark tools' own pieces that a measurement rests on: the sphere-light room that
# tools/scenes/make_bench_scenes.py writes (docs/performance-history/round-29.md) is the scene it says,
# and tools/bench/bench-render-ab reads the header that `penumbra render` wrote. Standard library
# only, beside the CLI.
import importlib.machinery
import importlib.util
import json

from conftest import SOURCE_DIR


def load_tool(name, file_name):
    """A tool of tools/ (its path below tools/) as a module (bench-render-ab has no .py)."""
    path = str(SOURCE_DIR / "tools" / file_name)
    loader = importlib.machinery.SourceFileLoader(name, path)
    module = importlib.util.module_from_spec(importlib.util.spec_from_loader(name, loader))
    loader.exec_module(module)
    return module


def sphere_room():
    return load_tool("make_bench_scenes", "scenes/make_bench_scenes.py").sphere_room()


def test_sphere_room_is_diffuse_quads_and_three_sphere_lights():
    room = sphere_room()
    lights = [s for s in room["shapes"] if "emission" in s]
    walls = [s for s in room["shapes"] if "emission" not in s]
    assert sorted(s["radius"] for s in lights) == [0.08, 0.3, 0.6]
    assert all(s["type"] == "sphere" for s in lights)
    assert walls and all(s["type"] == "quad" for s in walls)
    assert all(m["type"] == "diffuse" for m in room["materials"].values())
    # The direct integrator's defaults: no strategy or sampling named.
    assert room["integrator"] == {"type": "direct"}
    assert (room["film"]["width"], room["film"]["height"], room["sampler"]["spp"]) == (128, 128, 256)


def test_bench_render_ab_reads_the_header_penumbra_wrote(cli, tmp_path):
    scene = tmp_path / "room.json"
    scene.write_text(json.dumps(sphere_room()))
    out = tmp_path / "room.exr"
    done = cli("render", scene, "--spp", 3, "--seed", 7, "--width", 32, "--height", 32, "--quiet", "-o", out)
    assert done.returncode == 0, done.stderr
    tool = load_tool("bench_render_ab", "bench/bench-render-ab")
    attributes = tool.exr_attributes(str(out))
    assert attributes["penumbra:spp"] == 3 and attributes["penumbra:seed"] == 7
    assert attributes["penumbra:sampler"] == "sobol"
    assert json.loads(attributes["penumbra:integrator"])["sphere_sampling"] == "solid_angle"
    seconds = tool.exr_render_seconds(str(out))
    assert seconds == attributes["penumbra:render_seconds"] and 0 < seconds < 60
