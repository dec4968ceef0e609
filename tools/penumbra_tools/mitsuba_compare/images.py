"""EXR images as numpy arrays (through Mitsuba's Bitmap, which reads Penumbra's header
attributes too) and the relative MSE that `penumbra compare` reports."""
import os


def relmse(a, b):
    """mean of (a-b)^2/(b^2+1e-2), b the reference (as `penumbra compare`)."""
    import numpy as np
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return float(np.mean((a - b) ** 2 / (b * b + 1e-2)))


def read_exr(path):
    """(H x W x 3 float32 image, header attributes as a dict)."""
    import numpy as np
    import mitsuba as mi
    if not mi.variant():
        mi.set_variant("scalar_rgb")
    bmp = mi.Bitmap(path)
    meta = bmp.metadata()
    img = np.array(mi.TensorXf(bmp), dtype=np.float32)[:, :, :3]
    return img, {k: meta[k] for k in meta.keys()}


def write_exr(path, img):
    import numpy as np
    import mitsuba as mi
    tmp = path + ".tmp.exr"
    mi.Bitmap(np.ascontiguousarray(img, dtype=np.float32)).write(tmp)
    os.replace(tmp, path)
