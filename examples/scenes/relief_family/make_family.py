#!/usr/bin/env python3
# Writes the relief family the planner's search model is fitted and judged on
# (docs/planner.md, "The search model"): height maps as 8-bit grey PNG files
# (white high) made here from seeded value noise, and one scene per relief
# naming it, plus scenes over the library's procedural fields. Each scene
# holds one material; `parallax bench --search-model` measures it.
#   python3 make_family.py   (writes into this folder)
# Plain Python (no numpy): deterministic for a given seed.
import json
import math
import random
import struct
import zlib

N = 256


def write_png(path, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", N, N, 8, 0, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def lattice(cells, seed):
    rng = random.Random(seed)
    return [[rng.random() for _ in range(cells)] for _ in range(cells)]


def value_noise(x, y, grid, cells):
    # Smooth (quintic) interpolation of a periodic lattice: tiles seamlessly.
    gx, gy = x * cells, y * cells
    i, j = int(math.floor(gx)), int(math.floor(gy))
    fx, fy = gx - i, gy - j
    sx = fx * fx * fx * (fx * (fx * 6 - 15) + 10)
    sy = fy * fy * fy * (fy * (fy * 6 - 15) + 10)
    a = grid[j % cells][i % cells]
    b = grid[j % cells][(i + 1) % cells]
    c = grid[(j + 1) % cells][i % cells]
    d = grid[(j + 1) % cells][(i + 1) % cells]
    return (a * (1 - sx) + b * sx) * (1 - sy) + (c * (1 - sx) + d * sx) * sy


def fractal(cells, octaves, seed, gain=0.5):
    grids = [(cells << o, lattice(cells << o, seed + o)) for o in range(octaves)]
    def f(x, y):
        total, amp, norm = 0.0, 1.0, 0.0
        for c, g in grids:
            total += amp * value_noise(x, y, g, c)
            norm += amp
            amp *= gain
        return total / norm
    return f


def normalised(fn):
    vals = [[fn((i + 0.5) / N, (j + 0.5) / N) for i in range(N)] for j in range(N)]
    lo = min(min(r) for r in vals)
    hi = max(max(r) for r in vals)
    return [[int(round(255 * (v - lo) / (hi - lo))) for v in r] for r in vals]


def field(name):
    if name.startswith("noise"):
        cells = {"noise_4": 4, "noise_16": 16, "noise_48": 48}[name]
        return normalised(fractal(cells, 3 if cells < 48 else 2, 11 + cells))
    if name == "plateaus":  # terraces with cliffs between them
        f = fractal(6, 3, 7)
        return normalised(lambda x, y: math.floor(f(x, y) * 6.0) / 6.0)
    if name == "dunes":  # asymmetric waves: a long windward slope, a steep lee face
        warp = fractal(3, 2, 5)
        def dune(x, y):
            p = (x * 6 + 0.8 * warp(x, y)) % 1.0
            return p / 0.8 if p < 0.8 else (1.0 - p) / 0.2
        return normalised(dune)
    if name == "ridges":  # ridged noise: sharp crests, broad valleys
        f = fractal(8, 3, 3)
        return normalised(lambda x, y: (1.0 - abs(2.0 * f(x, y) - 1.0)) ** 2)
    if name == "plaster":  # fine grain over soft blobs
        soft, grain = fractal(5, 2, 17), fractal(64, 1, 19)
        return normalised(lambda x, y: 0.75 * soft(x, y) + 0.25 * grain(x, y))
    if name == "craters":  # round pits with raised rims
        rng = random.Random(23)
        holes = [(rng.random(), rng.random(), 0.04 + 0.08 * rng.random()) for _ in range(14)]
        def crater(x, y):
            h = 0.5
            for cx, cy, r in holes:
                dx = min(abs(x - cx), 1 - abs(x - cx))
                dy = min(abs(y - cy), 1 - abs(y - cy))
                d = math.hypot(dx, dy) / r
                if d < 1.0:
                    h = min(h, 0.5 - 0.5 * (1.0 - d * d))
                elif d < 1.4:
                    h = max(h, 0.5 + 0.4 * math.sin(math.pi * (d - 1.0) / 0.4))
            return h
        return normalised(crater)
    raise ValueError(name)


IMAGES = ["noise_4", "noise_16", "noise_48", "plateaus", "dunes", "ridges", "plaster", "craters"]
# name -> (height source, height_scale); the fit set first, then the judge set.
RELIEFS = {
    # fit: the shipped table's five, and two of the family
    "sine_4": ({"procedural": "sine", "size": N, "frequency": 4}, 0.08),
    "bricks": ({"procedural": "bricks", "size": N}, 0.06),
    "text": ({"procedural": "text", "size": N, "text": "PARALLAX"}, 0.05),
    "hemispheres": ({"procedural": "hemispheres", "size": N, "count": 6}, 0.06),
    "lines_1": ({"procedural": "lines", "size": N, "count": 24}, 0.04),
    "noise_16": ({"file": "noise_16.png"}, 0.06),
    "plateaus": ({"file": "plateaus.png"}, 0.05),
    # judge: never seen by the fit
    "noise_4": ({"file": "noise_4.png"}, 0.1),
    "noise_48": ({"file": "noise_48.png"}, 0.03),
    "dunes": ({"file": "dunes.png"}, 0.06),
    "ridges": ({"file": "ridges.png"}, 0.07),
    "plaster": ({"file": "plaster.png"}, 0.02),
    "craters": ({"file": "craters.png"}, 0.06),
    "sine_24": ({"procedural": "sine", "size": N, "frequency": 24}, 0.08),
    "cones_24": ({"procedural": "cones", "size": N, "count": 24}, 0.08),
    "lines_wide": ({"procedural": "lines", "size": N, "count": 6, "line_width": 16}, 0.06),
    "pit": ({"procedural": "pit", "size": N}, 0.08),
    "bricks_shallow": ({"procedural": "bricks", "size": N}, 0.01),
}
FIT = ["sine_4", "bricks", "text", "hemispheres", "lines_1", "noise_16", "plateaus"]

if __name__ == "__main__":
    for name in IMAGES:
        write_png(name + ".png", field(name))
    for name, (height, scale) in RELIEFS.items():
        group = "fit" if name in FIT else "judge"
        scene = {"name": name, "camera": {"position": [0, -2, 1.2], "target": [0, 0, 0]},
                 "lights": [{"type": "directional", "direction": [-0.5, 0.3, -0.8]}],
                 "materials": [{"name": name, "height": height, "height_scale": scale}],
                 "objects": [{"name": "ground", "mesh": {"type": "plane", "size": 2.4}, "material": name}]}
        with open(f"{group}_{name}.json", "w") as f:
            json.dump(scene, f, indent=1)
            f.write("\n")
    print(len(IMAGES), "height maps,", len(RELIEFS), "scenes")
