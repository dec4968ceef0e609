"""Whether two renderers agree: Penumbra's reference against a Mitsuba render, judged
against the noise between two Mitsuba renders (per pixel and per 8x8 block); and the
time at which a series of renders reaches a target error."""
import math

from penumbra_tools.mitsuba_compare.images import relmse


def block_means(img, b=8):
    H, W, C = img.shape
    h, w = H // b, W // b
    return img[:h * b, :w * b].reshape(h, b, w, b, C).mean(axis=(1, 3))


def agreement(ref, m1, m2):
    import numpy as np
    bp, b1, b2 = block_means(ref), block_means(m1), block_means(m2)
    d = np.abs(b1 - bp).mean(axis=2) / (bp.mean(axis=2) + 0.05)
    # Worst block judged against the noise between the two Mitsuba renders there.
    noise = np.abs(b1 - b2).mean(axis=2) / (bp.mean(axis=2) + 0.05) + 1e-6
    z = d / np.maximum(noise, np.median(noise))
    by, bx = np.unravel_index(np.argmax(z), z.shape)
    H, W, _ = ref.shape
    return {
        "relmse": relmse(m1, ref),
        "noise_relmse": relmse(m1, m2),
        "block_relmse": relmse(b1, bp),
        "block_noise_relmse": relmse(b1, b2),
        "mean_ratio": [float(m1[..., c].mean() / max(ref[..., c].mean(), 1e-12)) for c in range(3)],
        "worst_block": {"x": int(bx * 8), "y": int(by * 8), "size": 8, "rel_diff": float(d[by, bx]),
                        "noise": float(noise[by, bx]), "penumbra": bp[by, bx].tolist(),
                        "mitsuba": b1[by, bx].tolist(), "image": [W, H]},
    }


def verdict(a):
    """Match when the difference Penumbra-Mitsuba looks like noise: relMSE not much above the
    Mitsuba-vs-Mitsuba floor, 8x8 block means likewise, mean ratios within 2%."""
    ok = a["relmse"] < 3 * a["noise_relmse"] + 1e-4 and a["block_relmse"] < 4 * a["block_noise_relmse"] + 1e-4 \
        and all(abs(r - 1) < 0.02 for r in a["mean_ratio"])
    return "match" if ok else "MISMATCH"


def time_to_error(points, target):
    """Seconds at which relMSE reaches target, log-log interpolated between the renders that
    bracket it; None when the last render is still above it. points: [spp, seconds, relMSE]."""
    for i, (_, t, e) in enumerate(points):
        if e < target:
            if i == 0:
                return t * e / target if e > 0 else t  # error ~ 1/time: extrapolate down
            _, t0, e0 = points[i - 1]
            f = (math.log(target) - math.log(e0)) / (math.log(e) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t) - math.log(t0)))
    return None
