#!/usr/bin/env python3
"""Writes an equirectangular sky with a small bright sun as a Radiance HDR file (run from the
repository root; default scenes/sky_sun.hdr, which scenes/environment_sun.json uses).

Nothing is downloaded: a clear sky brightening towards the horizon, a dim ground below it, and
a sun of 1.5 degrees radius (0.002 sr), 35 degrees above the horizon, about 10^4 times as
bright as the sky, so that it gives most of the light. Orientation as SCENE_FORMAT.md
`environment`: row 0 at +y, u = atan2(x, -z) / (2 pi). The file is flat RGBE (Greg Ward, "Real Pixels", Graphics Gems II): 4 bytes per texel.
"""
import argparse
import math
import struct


def sky(d):
    """Linear RGB radiance arriving from unit direction d (pointing away from the scene)."""
    x, y, z = d
    sun = (math.cos(math.radians(35)) * math.sin(math.radians(-60)), math.sin(math.radians(35)),
           -math.cos(math.radians(35)) * math.cos(math.radians(-60)))
    cos_sun = sum(a * b for a, b in zip(d, sun))
    if cos_sun > math.cos(math.radians(1.5)):
        return (6000.0, 5400.0, 4400.0)
    if y < 0:
        return (0.06, 0.05, 0.04)
    horizon = (1 - y) ** 4  # brighter and whiter towards the horizon
    glow = 2.0 * max(cos_sun, 0.0) ** 32  # a halo about the sun
    return (0.25 + 0.9 * horizon + glow, 0.45 + 0.8 * horizon + glow, 1.0 + 0.5 * horizon + 0.5 * glow)


def rgbe(c):
    largest = max(c)
    if largest < 1e-32:
        return b"\0\0\0\0"
    mantissa, exponent = math.frexp(largest)
    scale = mantissa * 256.0 / largest
    return struct.pack("BBBB", *(min(255, int(v * scale)) for v in c), exponent + 128)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", default="scenes/sky_sun.hdr")
    parser.add_argument("--width", type=int, default=512)
    parser.add_argument("--height", type=int, default=256)
    args = parser.parse_args()
    w, h = args.width, args.height
    rows = []
    for row in range(h):
        for col in range(w):
            # The texel's centre direction (the inverse of the contract's lookup).
            phi = 2 * math.pi * (col + 0.5) / w
            theta = math.pi * (row + 0.5) / h
            d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
            rows.append(rgbe(sky(d)))
    with open(args.output, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
        f.write(b"".join(rows))


if __name__ == "__main__":
    main()
