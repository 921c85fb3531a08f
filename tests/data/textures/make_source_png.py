# Writes a 64x64 RGB test image (smooth gradients, a disc, a stripe) as PNG.
import struct, zlib, sys, math
W = H = 64
rows = []
for y in range(H):
    row = bytearray([0])
    for x in range(W):
        r = 255 * x // (W - 1)
        g = 255 * y // (H - 1)
        b = int(128 + 100 * math.sin(x / 6.0) * math.cos(y / 9.0))
        dx, dy = x - 40, y - 24
        if dx * dx + dy * dy < 100:
            r, g, b = 250, 240, 40
        if 8 <= x < 12:
            r, g, b = 20, 30, 200
        row += bytes([r, g, b])
    rows.append(bytes(row))
def chunk(t, d):
    return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0))
png += chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b"")
open(sys.argv[1], "wb").write(png)
