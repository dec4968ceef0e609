"""Penumbra's renderer for scripts: scenes in, numpy arrays out (docs/guide/python.md).

    import penumbra
    img = penumbra.render("scenes/cornell.json", spp=16, seed=1)   # or a dict scene
    img["rgb"]                      # float32 (height, width, 3), scene-linear radiance
    img = penumbra.render("scenes/cornell.json", spp=4, aovs=["depth", "shape_id"])
    img["depth"], img["shape_id"]   # float32 (height, width), uint32 (height, width)
    r = penumbra.Renderer("scenes/cornell.json", width=64, height=64)
    frame = r.render(spp=4, set={"camera.eye": [0, 1, 4]})     # no recompilation
    penumbra.write_exr("out.exr", img)                        # as `penumbra render` writes
    clean = penumbra.denoise(img["rgb"])    # Open Image Denoise, with pip install penumbra[denoise]

Bad input raises SceneError (a ValueError) with the command line's one-line message;
other failures raise RenderError. Rendering releases the GIL; Ctrl-C raises
KeyboardInterrupt within a second (when rendering from the main thread, where Python
runs its signal handlers).
"""


class Layers(dict):
    """A rendered or read image: layer name -> numpy array ("rgb": float32 (H, W, 3)).

    AOV layers (aovs=, or film.aovs) follow "rgb" by name: "albedo", "normal", "position",
    "variance" float32 (H, W, 3), "depth" float32 (H, W), "shape_id", "primitive_id",
    "material_id" uint32 (H, W). write_exr writes them as the EXR's channels.

    `meta` holds the EXR header attributes without their "penumbra:" prefix (spp, seed,
    sample_offset, integrator, render_seconds, sampler; pieces for merged files), which
    write_exr writes back.
    """

    def __init__(self, *args, meta=None, **kwargs):
        super().__init__(*args, **kwargs)
        self.meta = dict(meta or {})

    def __repr__(self):
        shapes = ", ".join(f"{k!r}: {v.dtype}{tuple(v.shape)}" for k, v in self.items())
        return f"Layers({{{shapes}}}, meta={self.meta!r})"


from ._penumbra import (  # noqa: E402  (Layers first: the extension builds them)
    Renderer,
    RenderError,
    SceneError,
    devices,
    false_color,
    read_exr,
    write_exr,
    write_png,
)
from .denoise import denoise  # noqa: E402  (pyoidn is imported by the first call only)


def render(scene, spp=None, seed=None, width=None, height=None, set=None, aovs=None, device=None):
    """Renders `scene` (a path, or a dict of the same JSON) once; returns Layers.

    spp, seed, width, height are shorthands for set={"sampler.spp": ..., ...}, applied
    after `set` as on the command line; aovs=["depth", ...] is film.aovs (--aov), each
    layer then one more entry of the result; `device` is a Vulkan device index (devices()).
    """
    renderer = Renderer(scene, spp=spp, seed=seed, width=width, height=height, set=set, aovs=aovs,
                        device=device)
    return renderer.render()


__all__ = ["Layers", "Renderer", "RenderError", "SceneError", "denoise", "devices", "false_color", "read_exr", "render", "write_exr", "write_png"]
