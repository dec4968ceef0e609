"""Penumbra's environment map (`environment` with `file`, docs/SCENE_FORMAT.md) as Mitsuba 3's
`envmap`, for tools/penumbra_tools/mitsuba_penumbra.py. Both use the same orientation (u = atan2(d.x, -d.z) /
(2 pi), v = acos(d.y) / pi, row 0 at +y). Two differences are bridged by writing a copy of the
map into a work folder:
- `radiance` is a per-channel factor in Penumbra, one scalar `scale` in Mitsuba: the copy is
  multiplied by it;
- Penumbra's texels are constant over their area, Mitsuba's envmap filters bilinearly: the
  copy repeats every texel UPSAMPLE x UPSAMPLE times, so that bilinear filtering only blends
  within half a new texel of an old texel's edge. The blend there is symmetric, so the
  map's integral (what the image's mean depends on) is kept up to the sin(theta) weighting
  across a strip of 1/(2 UPSAMPLE) texel.
The light's selection weight is Penumbra's power 4 pi^2 R^2 L_mean, L_mean the map's mean
radiance over solid angle (host/render/light_arrays.cpp, lightPower)."""
import hashlib
import math
import os
import tempfile

import numpy as np
import mitsuba as mi

UPSAMPLE = 4


def _work_dir():
    d = os.path.join(tempfile.gettempdir(), "penumbra-mitsuba-envmaps")
    os.makedirs(d, exist_ok=True)
    return d


def mean_radiance(texels):
    """Mean over solid angle of an H x W x 3 equirectangular map: each row's texels cover
    (2 pi / W)(cos theta_top - cos theta_bottom) steradians."""
    H = texels.shape[0]
    theta = np.linspace(0.0, math.pi, H + 1)
    w = (np.cos(theta[:-1]) - np.cos(theta[1:])) / 2.0  # the rows' shares of the sphere
    return (texels.mean(axis=1) * w[:, None]).sum(axis=0)


def envmap_dict(path, radiance, scene_radius, power_weights):
    """The translated emitter dict (the scaled, upsampled copy is written on first use)."""
    bmp = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    texels = np.array(bmp, dtype=np.float64)[:, :, :3] * np.asarray(radiance, dtype=np.float64)
    big = np.repeat(np.repeat(texels, UPSAMPLE, axis=0), UPSAMPLE, axis=1).astype(np.float32)
    key = hashlib.sha1(big.tobytes()).hexdigest()[:16]
    out = os.path.join(_work_dir(), f"{key}.exr")
    if not os.path.exists(out):
        tmp = f"{out}.{os.getpid()}.tmp.exr"
        mi.Bitmap(big).write(tmp)
        os.replace(tmp, out)
    L = mean_radiance(texels)
    weight = max(4 * math.pi ** 2 * scene_radius ** 2 * float(L.mean()), 1e-12) if power_weights else 1.0
    return {"type": "envmap", "filename": out, "sampling_weight": weight}
