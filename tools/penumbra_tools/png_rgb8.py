"""8-bit RGB PNG files with the standard library (zlib): read_png for the non-interlaced
8-bit RGB and RGBA files that `penumbra render --png` and Mitsuba's Bitmap write, write_png for
figures. The format: the PNG specification (W3C, 2003), sections 5 (chunks), 9 (filters)."""
import struct
import zlib

SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _paeth(a, b, c):
    """The Paeth predictor (PNG specification section 9.4): whichever of left, up, upper-left
    is closest to left + up - upper-left."""
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def read_png(path):
    """(width, height, bytearray of 8-bit RGB rows); alpha, if any, is dropped."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != SIGNATURE:
        raise ValueError(f"{path}: not a PNG file")
    i, idat, header = 8, [], None
    while i < len(data):
        (n,) = struct.unpack(">I", data[i:i + 4])
        kind, body = data[i + 4:i + 8], data[i + 8:i + 8 + n]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        i += 12 + n
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace != 0:
        raise ValueError(f"{path}: only 8-bit RGB or RGBA non-interlaced PNGs are read")
    bpp = 3 if colour == 2 else 4
    raw = zlib.decompress(b"".join(idat))
    stride = width * bpp
    prev = bytearray(stride)
    rgb = bytearray()
    for y in range(height):
        kind = raw[y * (stride + 1)]
        row = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = row[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            pred = (0, a, b, (a + b) >> 1, _paeth(a, b, c))[kind]
            row[x] = (row[x] + pred) & 0xFF
        prev = row
        if bpp == 3:
            rgb += row
        else:
            for x in range(width):
                rgb += row[4 * x:4 * x + 3]
    return width, height, rgb


def _chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


def write_png(path, width, height, rgb):
    """Writes 8-bit RGB rows; each row filtered with Sub (section 9.2: the difference from its
    left neighbour), which suits the figures' smooth backgrounds and costs noise nothing."""
    stride = 3 * width
    out = bytearray()
    for y in range(height):
        row = rgb[y * stride:(y + 1) * stride]
        out.append(1)
        out += bytes((row[x] - (row[x - 3] if x >= 3 else 0)) & 0xFF for x in range(stride))
    with open(path, "wb") as f:
        f.write(SIGNATURE + _chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                + _chunk(b"IDAT", zlib.compress(bytes(out), 9)) + _chunk(b"IEND", b""))
