#!/usr/bin/env python3
"""Writes the image fuzz target's seed corpus: small PNGs of every colour
type, depth and interlacing the loader takes, an indexed PNG with a short
palette, and TGA files (plain, RLE, colour-mapped). Seeds are tiny so the
fuzzer mutates structure, not pixels. Usage: make_image_seeds.py OUT_DIR"""
import struct
import sys
import zlib
from pathlib import Path


def chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


# Adam7 passes: (x0, y0, dx, dy).
ADAM7 = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]


def png(w, h, depth, colour_type, rows, interlace=0, extra=b"", bpp=3):
    """rows: w * bpp bytes each (8-bit depths); interlaced images are split
    into their seven Adam7 passes, each row with its filter byte."""
    ihdr = struct.pack(">IIBBBBB", w, h, depth, colour_type, 0, 0, interlace)
    if interlace:
        raw = b""
        for x0, y0, dx, dy in ADAM7:
            xs = range(x0, w, dx)
            for y in range(y0, h, dy):
                if len(xs):
                    raw += b"\x00" + b"".join(rows[y][x * bpp:(x + 1) * bpp] for x in xs)
    else:
        raw = b"".join(b"\x00" + r for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + extra +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main(out):
    out.mkdir(parents=True, exist_ok=True)
    w = h = 4
    grey = [bytes((x * 60 + y * 10) & 0xFF for x in range(w)) for y in range(h)]
    rgb = [bytes(v for x in range(w) for v in (x * 60, y * 60, 128)) for y in range(h)]
    rgba = [bytes(v for x in range(w) for v in (x * 60, y * 60, 128, 200)) for y in range(h)]
    grey_alpha = [bytes(v for x in range(w) for v in (x * 60, 255 - y * 30)) for y in range(h)]
    grey16 = [b"".join(struct.pack(">H", (x * 9000 + y * 100) & 0xFFFF) for x in range(w)) for y in range(h)]
    rgba16 = [b"".join(struct.pack(">HHHH", x * 9000, y * 9000, 30000, 65535) for x in range(w)) for y in range(h)]
    indices = [bytes((x + y) % 3 for x in range(w)) for y in range(h)]
    palette = chunk(b"PLTE", bytes((255, 0, 0, 0, 255, 0, 0, 0, 255)))
    trns = chunk(b"tRNS", bytes((255, 128)))
    one_bit = [bytes((0b10100000 if y % 2 else 0b01010000,)) for y in range(h)]
    files = {
        "grey8.png": png(w, h, 8, 0, grey),
        "grey1.png": png(w, h, 1, 0, one_bit),
        "grey16.png": png(w, h, 16, 0, grey16),
        "grey_alpha.png": png(w, h, 8, 4, grey_alpha),
        "rgb8.png": png(w, h, 8, 2, rgb),
        "rgba8.png": png(w, h, 8, 6, rgba),
        "rgba16.png": png(w, h, 16, 6, rgba16),
        "indexed_short_palette.png": png(w, h, 8, 3, indices, extra=palette + trns),
        "rgb8_interlaced.png": png(w, h, 8, 2, rgb, interlace=1),
    }
    # TGA: 18-byte header, then (for type 1) the colour map, then pixels
    # bottom row first (BGR(A)).
    def tga(image_type, depth, body, cmap=b"", cmap_len=0, descriptor=0):
        header = struct.pack("<BBBHHBHHHHBB", 0, 1 if cmap else 0, image_type, 0, cmap_len,
                             24 if cmap else 0, 0, 0, w, h, depth, descriptor)
        return header + cmap + body
    bgr = b"".join(bytes((128, y * 60, x * 60)) for y in range(h) for x in range(w))
    files["rgb24.tga"] = tga(2, 24, bgr)
    # RLE: each row one run packet of 4 pixels.
    rle = b"".join(bytes((0x80 | (w - 1), 40 * y, 80, 200)) for y in range(h))
    files["rgb24_rle.tga"] = tga(10, 24, rle)
    cmap = bytes((0, 0, 255, 0, 255, 0, 255, 0, 0))
    files["colour_mapped.tga"] = tga(1, 8, bytes((x + y) % 3 for y in range(h) for x in range(w)), cmap, 3)
    for name, data in files.items():
        (out / name).write_bytes(data)


if __name__ == "__main__":
    main(Path(sys.argv[1]))
