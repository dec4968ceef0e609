"""penumbra.denoise: Intel Open Image Denoise's "RT" filter on a rendered image (optional).

The denoiser comes from PyPI's pyoidn (it bundles OIDN and its CPU device), installed by
`pip install penumbra[denoise]` and imported only when denoise() is first called, so that
`import penumbra` never needs it. docs/guide/python.md ("Denoising") shows what it does to
the Cornell box at 4 spp.

The result is a biased estimate (a learned filter, Áfra et al., "Intel Open Image Denoise",
2019-); the noisy image stays the unbiased one, which is why `penumbra render --denoise`
keeps both in the EXR.
"""

import numpy as np

INSTALL_HINT = "penumbra.denoise needs pyoidn: pip install penumbra[denoise] (or pip install pyoidn)"


def _pyoidn():
    """The pyoidn module, or a one-line ImportError naming the package to install."""
    try:
        import pyoidn
    except ImportError as error:
        raise ImportError(f"{INSTALL_HINT} ({error})") from None
    return pyoidn


def _image(value, name, shape):
    """`value` as a contiguous float32 (h, w, 3) array of finite values, else a one-line ValueError."""
    try:
        image = np.ascontiguousarray(value, dtype=np.float32)
    except (TypeError, ValueError):
        raise ValueError(f"denoise: {name} must be a float array of shape (height, width, 3)") from None
    if image.ndim != 3 or image.shape[2] != 3 or 0 in image.shape:
        raise ValueError(f"denoise: {name} has shape {image.shape}, expected (height, width, 3)")
    if shape is not None and image.shape != shape:
        raise ValueError(f"denoise: {name} has shape {image.shape}, rgb has {shape}")
    if not np.isfinite(image).all():
        raise ValueError(f"denoise: {name} has NaN or infinite values")
    return image


def denoise(rgb, albedo=None, normal=None):
    """Denoises `rgb` (scene-linear radiance, (h, w, 3)); returns a new float32 (h, w, 3).

    albedo and normal are the "albedo" and "normal" AOV layers of the same render
    (aovs=["albedo", "normal"]): OIDN's auxiliary images, which keep edges and textures
    sharp. OIDN takes a normal only together with an albedo, so normal alone is refused.
    Raises ValueError on bad arguments and ImportError when pyoidn is not installed.
    """
    if normal is not None and albedo is None:
        raise ValueError("denoise: normal needs albedo too (Open Image Denoise uses a normal only with an albedo)")
    color = _image(rgb, "rgb", None)
    aux = {}
    if albedo is not None:
        aux["albedo"] = _image(albedo, "albedo", color.shape)
    if normal is not None:
        aux["normal"] = _image(normal, "normal", color.shape)
    pyoidn = _pyoidn()
    # hdr: radiance is unbounded (OIDN's "RT" filter, hdr=true); the AOVs are the noisy
    # per-pixel means of the same samples, so OIDN prefilters them (clean_aux=False).
    output = pyoidn.denoise(color, hdr=True, quality="high", **aux)
    if not np.isfinite(output).all():  # never a silent wrong image
        raise RuntimeError("denoise: Open Image Denoise returned NaN or infinite values")
    return output
