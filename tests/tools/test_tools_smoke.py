# The developer tools under tools/ still run: each Python tool answers --help, each shell
# tool parses, and the generators reproduce the committed files they generate byte for byte
# (scenes/*.json, scenes/models/torus_knot.*, scenes/sky_sun.hdr), so that a change to a
# generator or a hand edit of its output cannot drift apart unnoticed.
# Registered in CTest by tests/CMakeLists.txt (tools.test_tools_smoke); pyflakes checks the
# same files in tools/dev/lint.
import filecmp
import os
import pathlib
import subprocess
import sys

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("PENUMBRA_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
TOOLS = SOURCE_DIR / "tools"

# Python tools with an argparse command line. tools/penumbra_tools/mitsuba_penumbra.py is a module that
# needs Mitsuba (the translation test covers it); make_models.py, make_scenes.py and
# make_sky.py are run for real below.
HELP_TOOLS = ["bench/bench-ab", "bench/bench-instructions", "bench/bench-many-lights", "bench/bench-python-orbit",
              "bench/kernel-profile", "scenes/make_bench_scenes.py", "scenes/make_instances_scene.py",
              "scenes/make_many_lights.py", "scenes/make_sky.py", "mesa/mesa-compare", "mesa/mesa-sid",
              "mitsuba/mitsuba_compare.py", "penumbra_tools/startup_bench.py"]


def shell_tools():
    out = []
    for path in sorted(TOOLS.rglob("*")):
        if path.is_file() and path.read_bytes()[:2] == b"#!":
            first = path.read_text(errors="replace").splitlines()[0]
            if "bash" in first or first.endswith("/sh"):
                out.append(path)
    return out


@pytest.mark.parametrize("tool", HELP_TOOLS)
def test_python_tool_answers_help(tool, tmp_path):
    r = subprocess.run([sys.executable, str(TOOLS / tool), "--help"], cwd=tmp_path, capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0, r.stderr
    assert "usage" in r.stdout.lower() or len(r.stdout.splitlines()) > 2, r.stdout
    assert list(tmp_path.iterdir()) == [], "--help wrote files"


def test_every_shell_tool_parses():
    tools = shell_tools()
    assert len(tools) >= 10, tools  # the setup, test, bench, mesa and slurm scripts
    for path in tools:
        r = subprocess.run(["bash", "-n", str(path)], capture_output=True, text=True, timeout=60)
        assert r.returncode == 0, f"{path}: {r.stderr}"


def test_make_scenes_reproduces_the_committed_scenes(tmp_path):
    subprocess.run([sys.executable, str(TOOLS / "scenes" / "make_scenes.py")], cwd=tmp_path, check=True, timeout=120)
    made = sorted(p.name for p in (tmp_path / "scenes").iterdir())
    assert made, "make_scenes.py wrote nothing"
    for name in made:
        assert filecmp.cmp(tmp_path / "scenes" / name, SOURCE_DIR / "scenes" / name, shallow=False), name


def test_make_models_reproduces_the_committed_model(tmp_path):
    subprocess.run([sys.executable, str(TOOLS / "scenes" / "make_models.py"), str(tmp_path)], check=True, timeout=300,
                   capture_output=True)
    for name in ("torus_knot.gltf", "torus_knot.glb"):
        assert filecmp.cmp(tmp_path / name, SOURCE_DIR / "scenes" / "models" / name, shallow=False), name


def test_make_sky_reproduces_the_committed_map(tmp_path):
    out = tmp_path / "sky.hdr"
    subprocess.run([sys.executable, str(TOOLS / "scenes" / "make_sky.py"), "-o", str(out)], check=True, timeout=300)
    assert filecmp.cmp(out, SOURCE_DIR / "scenes" / "sky_sun.hdr", shallow=False)
