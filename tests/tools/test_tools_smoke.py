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
              "mitsuba/mitsuba_compare.py", "penumbra_tools/startup_bench.py", "figures/many_lights_figure.py"]


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


# The many-lights tools' pieces that need no renderer: the generator's scene kinds, the PNG
# codec and the figure's layout and equal-time search (tools/figures/many_lights_figure.py).
sys.path.insert(0, str(TOOLS))


def _load(relative):
    import importlib.util
    spec = importlib.util.spec_from_file_location(pathlib.Path(relative).stem, TOOLS / relative)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _cross_y(a, b, c):
    """The y component of (b - a) x (c - a): negative for a triangle or quad facing down."""
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    return u[2] * v[0] - u[0] * v[2]


def test_make_many_lights_mesh_and_quads_face_down(tmp_path):
    import json
    import struct
    gen = TOOLS / "scenes" / "make_many_lights.py"
    subprocess.run([sys.executable, str(gen), "--kind", "mesh", "--grid", "10", "--out", str(tmp_path / "m.json")],
                   check=True, capture_output=True, timeout=60)
    scene = json.loads((tmp_path / "m.json").read_text())
    (mesh,) = [s for s in scene["shapes"] if s["type"] == "mesh"]
    data = (tmp_path / mesh["file"]).read_bytes()
    header, body = data.split(b"end_header\n", 1)
    assert b"element vertex 121" in header and b"element face 200" in header  # an 11 x 11 grid of vertices
    pos = [struct.unpack_from("<3f", body, 12 * i) for i in range(121)]
    faces = [struct.unpack_from("<B3i", body, 12 * 121 + 13 * i) for i in range(200)]
    assert all(f[0] == 3 and _cross_y(pos[f[1]], pos[f[2]], pos[f[3]]) < 0 for f in faces)  # emitting downwards
    subprocess.run([sys.executable, str(gen), "--kind", "quads", "--panels", "5", "--out", str(tmp_path / "q.json")],
                   check=True, capture_output=True, timeout=60)
    panels = [s for s in json.loads((tmp_path / "q.json").read_text())["shapes"] if "power" in s]
    assert len(panels) == 25
    for q in panels:
        o, u, v = q["origin"], q["edge_u"], q["edge_v"]
        assert _cross_y(o, [o[i] + u[i] for i in range(3)], [o[i] + v[i] for i in range(3)]) < 0


def _filter_rows(rows, bpp, kinds):
    """PNG rows (bytes) filtered with the given filter type per row, written straight from the
    PNG specification's section 9.2 formulas (independently of penumbra_tools/png_rgb8.py)."""
    out, prev = bytearray(), bytes(len(rows[0]))
    for row, kind in zip(rows, kinds):
        out.append(kind)
        for x in range(len(row)):
            a = row[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            p = a + b - c
            paeth = min((abs(p - a), 0, a), (abs(p - b), 1, b), (abs(p - c), 2, c))[2]
            out.append((row[x] - (0, a, b, (a + b) // 2, paeth)[kind]) & 0xFF)
        prev = row
    return bytes(out)


def test_png_reader_undoes_every_filter_and_reads_what_the_writer_wrote(tmp_path):
    import random
    import struct
    import zlib
    from penumbra_tools.png_rgb8 import SIGNATURE, _chunk, read_png, write_png
    rng = random.Random(5)
    w, h = 7, 10
    rgba = [bytes(rng.randrange(256) for _ in range(4 * w)) for _ in range(h)]
    kinds = [k % 5 for k in range(h)]
    path = tmp_path / "filters.png"
    path.write_bytes(SIGNATURE + _chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
                     + _chunk(b"IDAT", zlib.compress(_filter_rows(rgba, 4, kinds))) + _chunk(b"IEND", b""))
    expected = bytearray()
    for row in rgba:
        for x in range(w):
            expected += row[4 * x:4 * x + 3]
    assert read_png(path) == (w, h, expected)
    write_png(tmp_path / "back.png", w, h, expected)
    assert read_png(tmp_path / "back.png") == (w, h, expected)


def test_many_lights_figure_layout(tmp_path):
    from penumbra_tools.png_rgb8 import read_png, write_png
    fig = _load("figures/many_lights_figure.py")
    w, h = 20, 6
    tiles = []
    for k in range(3):
        path = tmp_path / f"t{k}.png"
        write_png(path, w, h, bytes([10 + k, 20 + k, 30 + k]) * (w * h))
        tiles.append((path, "ab", "1.5"))
    fig.compose(tiles, 2, tmp_path / "fig.png")
    width, height, rgb = read_png(tmp_path / "fig.png")
    assert (width, height) == (fig.GAP + 2 * (w + fig.GAP), fig.GAP + 2 * (fig.LABEL_HEIGHT + h + fig.GAP))

    def pixel(x, y):
        return tuple(rgb[3 * (y * width + x):3 * (y * width + x) + 3])

    for k in range(3):  # each tile's corners, under its label strip
        x0 = fig.GAP + (k % 2) * (w + fig.GAP)
        y0 = fig.GAP + (k // 2) * (fig.LABEL_HEIGHT + h + fig.GAP) + fig.LABEL_HEIGHT
        assert pixel(x0, y0) == pixel(x0 + w - 1, y0 + h - 1) == (10 + k, 20 + k, 30 + k)
        assert pixel(x0 - 1, y0) == fig.BACKGROUND and pixel(x0 + w, y0 + h - 1) == fig.BACKGROUND
    label = [pixel(x, y) for x in range(fig.GAP, fig.GAP + w) for y in range(fig.GAP, fig.GAP + fig.LABEL_HEIGHT)]
    assert fig.INK in label  # the text was drawn


def test_many_lights_figure_equal_time_search():
    fig = _load("figures/many_lights_figure.py")
    calls = []

    def render(spp):  # a fixed cost and a cost per sample, as a render has
        calls.append(spp)
        return 0.3 + 0.01 * spp

    spp, seconds = fig.equal_time_spp(render, 1.0)
    assert abs(seconds - 1.0) <= 0.15 and seconds == render(spp) and len(calls) <= 6
    spp, _ = fig.equal_time_spp(render, 1.0, multiple=4)
    assert spp % 4 == 0
