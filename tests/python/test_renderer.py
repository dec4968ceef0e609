# penumbra.Renderer: re-renders with other overrides equal fresh renders, and the changes
# the format lets a script make between frames (camera, film size, spp, seed, material
# numbers, light powers) reuse the compiled kernel: Renderer.kernel_compilations counts the
# driver compilations (pipelines created, gpu/kernel_cache.h).
import threading
import time

import numpy as np
import pytest

import penumbra

BASE = dict(width=24, height=16, spp=2, seed=1)
# A point light beside the quad light, so that a light of the `lights` list has a power.
POINT = {"lights[0]": {"type": "point", "position": [0.3, 1.5, 0.5], "power": [5, 5, 5]}}

# Each a change a script makes between frames, none of which needs another kernel.
CHANGES = {
    "camera": {"set": {"camera.eye": [0.6, 1.2, 3.6], "camera.fov_y": 45}},
    "film size": {"width": 20, "height": 12},
    "spp and seed": {"spp": 3, "seed": 9},
    "material numbers": {"set": {"materials.red.albedo": [0.2, 0.5, 0.7]}},
    "emitter's radiance": {"set": {"shapes[7].emission": [30, 20, 10]}},
    "light power": {"set": {"lights[0].power": [1, 2, 3]}},
}


def fresh(cornell, change):
    """A render in a Renderer of its own, with `change` on top of BASE and POINT."""
    args = {**BASE, **{k: v for k, v in change.items() if k != "set"}}
    return penumbra.render(cornell, **args, set={**POINT, **change.get("set", {})})


@pytest.fixture
def renderer(cornell):
    r = penumbra.Renderer(cornell, set=POINT)
    r.render(**BASE)
    assert r.kernel_compilations >= 1
    return r


@pytest.mark.parametrize("name", list(CHANGES))
def test_rerender_equals_fresh_render_without_recompiling(renderer, cornell, name):
    change = CHANGES[name]
    compilations = renderer.kernel_compilations
    args = {**BASE, **{k: v for k, v in change.items() if k != "set"}}
    frame = renderer.render(**args, set=change.get("set"))
    assert renderer.kernel_compilations == compilations, f"{name} recompiled"
    expected = fresh(cornell, change)
    assert frame["rgb"].shape == expected["rgb"].shape
    np.testing.assert_array_equal(frame["rgb"], expected["rgb"])
    # and back: the original frame again, still without compiling
    again = renderer.render(**BASE)
    np.testing.assert_array_equal(again["rgb"], fresh(cornell, {})["rgb"])
    assert renderer.kernel_compilations == compilations


def test_uploads_reused_for_camera_and_sampler_only(renderer):
    uploads = renderer.scene_uploads
    renderer.render(**BASE, set={"camera.eye": [0, 1.1, 3.5]})
    renderer.render(**{**BASE, "spp": 1, "seed": 4})
    assert renderer.scene_uploads == uploads  # retargeted: only the render parameters
    renderer.render(**BASE, set={"materials.red.albedo": [0.3, 0.3, 0.3]})
    assert renderer.scene_uploads == uploads + 1  # uploaded anew, the pipeline reused


def test_other_kernels_compile_once_each(renderer):
    """Integrator options are specialization constants: a new strategy compiles a kernel,
    going back to one compiled before does not (the cache keeps it)."""
    compilations = renderer.kernel_compilations
    renderer.render(**BASE, set={"integrator.strategy": "light"})
    assert renderer.kernel_compilations == compilations + 1
    renderer.render(**BASE)
    renderer.render(**BASE, set={"integrator.strategy": "light"})
    assert renderer.kernel_compilations == compilations + 1


def test_failed_render_keeps_the_renderer_usable(renderer):
    with pytest.raises(penumbra.SceneError):
        renderer.render(set={"camera.fov_y": 200})
    compilations = renderer.kernel_compilations
    frame = renderer.render(**BASE)
    assert frame["rgb"].shape == (16, 24, 3) and renderer.kernel_compilations == compilations


def test_render_releases_the_gil(cornell):
    """Another Python thread runs while a render is under way."""
    r = penumbra.Renderer(cornell, width=64, height=64)
    ticks = 0
    done = threading.Event()

    def count():
        nonlocal ticks
        while not done.is_set():
            ticks += 1
            time.sleep(0.001)

    def ticks_during_render(spp):
        nonlocal ticks
        ticks = 0
        done.clear()
        thread = threading.Thread(target=count)
        start = time.monotonic()
        thread.start()
        r.render(spp=spp)
        seconds = time.monotonic() - start
        done.set()
        thread.join()
        return ticks, seconds

    # A render of at least a fifth of a second on this machine, whatever its speed and load: spp
    # doubled until the counted render itself lasts that long (an earlier, untimed probe does not
    # predict it: a short render's time is mostly fixed costs, and a shared machine's load varies).
    spp = 16
    ticks, seconds = ticks_during_render(spp)
    while seconds <= 0.2 and spp < 1 << 20:
        spp *= 2
        ticks, seconds = ticks_during_render(spp)
    # With the GIL held throughout, the counter would stand still (a tick or two at most);
    # released, it ticks about once a millisecond. A tenth of that leaves room for a busy machine.
    assert seconds > 0.2 and ticks > max(20, 0.1 * seconds * 1000), (ticks, seconds, spp)
