# examples/dataset.py: one EXR a frame of the orbit, each the render of its camera with its
# layers (rgb, depth, normal, shape_id, material_id), and the preview grid PNG, from a
# single Renderer (one kernel compilation, one upload).
import importlib.util
import json
import struct
import subprocess
import sys

import numpy as np

import penumbra


def test_dataset_example_writes_the_orbit(tmp_path):
    from conftest import SOURCE_DIR
    script = SOURCE_DIR / "examples" / "dataset.py"
    scene = SOURCE_DIR / "scenes" / "gltf_model.json"
    done = subprocess.run([sys.executable, str(script), "--scene", str(scene), "--frames", "3", "--size", "16", "12",
                           "--spp", "1", "--out", str(tmp_path)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert "3 frames of 16x12 at 1 spp" in done.stdout and "1 kernel compilations, 1 scene uploads" in done.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frame_000.exr", "frame_001.exr", "frame_002.exr",
                                                          "preview.png"]
    spec = importlib.util.spec_from_file_location("dataset", script)
    dataset = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(dataset)
    eyes = dataset.orbit(json.loads(scene.read_text())["camera"], 3)
    for i in (0, 2):
        expected = penumbra.render(scene, width=16, height=12, spp=1, seed=0, set={"camera.eye": eyes[i]},
                                   aovs=dataset.LAYERS)
        written = penumbra.read_exr(tmp_path / f"frame_{i:03d}.exr")
        assert list(written) == ["rgb", "depth", "normal", "shape_id", "material_id"]
        for name in written:
            np.testing.assert_array_equal(written[name], expected[name], err_msg=name)
        # The model and the floor are in view: more than one shape, and hits.
        assert len(np.unique(written["shape_id"])) >= 2 and np.isfinite(written["depth"]).any()
    # The grid: 3 frames shown, a row each, of rgb and the 4 layers' tiles.
    png = (tmp_path / "preview.png").read_bytes()
    assert png[12:16] == b"IHDR" and struct.unpack(">II", png[16:24]) == (5 * 16, 3 * 12)
