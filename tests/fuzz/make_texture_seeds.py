#!/usr/bin/env python3
"""Writes the texture container fuzz targets' seed corpora: small valid
KTX 1.1, KTX 2.0 (one Zstandard-supercompressed) and PVR v3 files of
different formats, arrays and cube maps, and a few malformed ones (each
refused by the reader, so the fuzzer starts at the checks too). Written
independently of the C++ writers, from the specifications. Seeds stay under
4 KB so the fuzzer mutates structure, not texels.

Zstandard: the `zstd` command compresses when it is installed; otherwise a
frame of raw blocks is built by hand (RFC 8878, section 3.1.1).

Usage: make_texture_seeds.py CORPUS_DIR   (writes CORPUS_DIR/{ktx1,ktx2,pvr})"""
import shutil
import struct
import subprocess
import sys
from pathlib import Path

KTX1_ID = b"\xabKTX 11\xbb\r\n\x1a\n"
KTX2_ID = b"\xabKTX 20\xbb\r\n\x1a\n"

# name: (block w, block h, block bytes, min blocks, GL internal, GL format, vkFormat, PVR code, channels)
FORMATS = {
    "r8": (1, 1, 1, 1, 0x8229, 0x1903, 9, None, 1),
    "rgb8": (1, 1, 3, 1, 0x8051, 0x1907, 23, None, 3),
    "rgba8": (1, 1, 4, 1, 0x8058, 0x1908, 37, None, 4),
    "etc2_rgb": (4, 4, 8, 1, 0x9274, 0, 147, 22, 3),
    "eac_r11": (4, 4, 8, 1, 0x9270, 0, 153, 25, 1),
    "astc_6x6": (6, 6, 16, 1, 0x93B4, 0, 165, 31, 4),
    "pvrtc1_rgb_4bpp": (4, 4, 8, 2, 0x8C00, 0, 0, 2, 3),
    "bc5": (4, 4, 16, 1, 0x8DBD, 0, 141, 13, 2),
}
BASE = {1: 0x1903, 2: 0x8227, 3: 0x1907, 4: 0x1908}


def image_bytes(fmt, w, h):
    bw, bh, bb, mb = FORMATS[fmt][:4]
    return max(-(-w // bw), mb) * max(-(-h // bh), mb) * bb


def chain(w, h):
    n, m = 1, max(w, h)
    while m > 1:
        m >>= 1
        n += 1
    return n


def extent(base, level):
    return max(1, base >> level)


def texels(n, seed):
    x = seed & 0xFFFFFFFF
    out = bytearray()
    for _ in range(n):
        x = (x * 1664525 + 1013904223) & 0xFFFFFFFF
        out.append(x >> 24)
    return bytes(out)


def images(fmt, w, h, levels, layers, faces, seed=1):
    """Per level, the list of layers * faces images (tightly packed rows)."""
    return [[texels(image_bytes(fmt, extent(w, i), extent(h, i)), seed + 97 * i + k)
             for k in range(layers * faces)] for i in range(levels)]


def pad4(b):
    return b + b"\0" * (-len(b) % 4)


def key_value(key, value):
    kv = key.encode() + b"\0" + value.encode() + b"\0"
    return pad4(struct.pack("<I", len(kv)) + kv)


def ktx1(fmt, w, h, levels=1, layers=1, faces=1):
    bw, bh, bb, mb, internal, gl_format, vk, pvr, ch = FORMATS[fmt]
    compressed = bw > 1
    kv = key_value("KTXorientation", "S=r,T=u")
    out = KTX1_ID + struct.pack("<13I", 0x04030201, 0 if compressed else 0x1401, 1, gl_format, internal,
                                BASE[ch] if compressed else gl_format, w, h, 0,
                                layers if layers > 1 else 0, faces, levels, len(kv)) + kv
    plain_cube = faces == 6 and layers == 1
    for i, level in enumerate(images(fmt, w, h, levels, layers, faces)):
        lw, lh = extent(w, i), extent(h, i)
        if not compressed:  # rows padded to 4 bytes
            row = lw * bb
            level = [b"".join(pad4(img[y * row:(y + 1) * row]) for y in range(lh)) for img in level]
        size = len(level[0]) if plain_cube else sum(len(x) for x in level)
        out += struct.pack("<I", size)
        for img in level:
            out += pad4(img) if plain_cube else img
        out = pad4(out)
    return out


def zstd_compress(data):
    if shutil.which("zstd"):
        return subprocess.run(["zstd", "-19", "-q", "-c", "--no-check"], input=data, check=True,
                              capture_output=True).stdout
    # A single-segment frame with the content size (4 bytes) and raw blocks.
    frame = struct.pack("<IB", 0xFD2FB528, 0xA0) + struct.pack("<I", len(data))
    blocks = [data[i:i + 65536] for i in range(0, len(data), 65536)] or [b""]
    for j, blk in enumerate(blocks):
        header = (len(blk) << 3) | (1 if j == len(blocks) - 1 else 0)
        frame += struct.pack("<I", header)[:3] + blk
    return frame


def dfd(fmt, supercompressed):
    bw, bh, bb, mb, internal, gl_format, vk, pvr, ch = FORMATS[fmt]
    if bw == 1:
        model, samples = 1, [(8 * i, 8, (0, 1, 2, 15)[i], 0, 255) for i in range(ch)]
    else:
        model = {"etc2_rgb": 161, "eac_r11": 161, "astc_6x6": 162, "pvrtc1_rgb_4bpp": 164, "bc5": 132}[fmt]
        samples = [(0, bb * 8 if fmt != "bc5" else 64, 2 if fmt == "etc2_rgb" else 0, 0, 0xFFFFFFFF)]
        if fmt == "bc5":
            samples.append((64, 64, 1, 0, 0xFFFFFFFF))
    size = 24 + 16 * len(samples)
    out = struct.pack("<7I", 4 + size, 0, 2 | size << 16, model | 1 << 8 | 1 << 16, (bw - 1) | (bh - 1) << 8,
                      0 if supercompressed else bb, 0)
    for off, bits, channel, lo, hi in samples:
        out += struct.pack("<4I", off | (bits - 1) << 16 | channel << 24, 0, lo, hi)
    return out


def ktx2(fmt, w, h, levels=1, layers=1, faces=1, zstd=False):
    bw, bh, bb, mb, internal, gl_format, vk, pvr, ch = FORMATS[fmt]
    d = dfd(fmt, zstd)
    kv = key_value("KTXorientation", "ru")
    head_len = 80 + 24 * levels
    dfd_off = head_len
    kvd_off = dfd_off + len(d)
    body = bytearray(d + kv)
    pos = kvd_off + len(kv)
    align = 1
    if not zstd:
        align = bb
        while align % 4:
            align += bb
    index = [None] * levels
    data = images(fmt, w, h, levels, layers, faces)
    for i in reversed(range(levels)):  # smallest level first
        raw = b"".join(data[i])
        payload = zstd_compress(raw) if zstd else raw
        padding = -pos % align
        body += b"\0" * padding
        pos += padding
        index[i] = (pos, len(payload), len(raw))
        body += payload
        pos += len(payload)
    out = KTX2_ID + struct.pack("<9I", vk, 1, w, h, 0, layers if layers > 1 else 0, faces, levels, 2 if zstd else 0)
    out += struct.pack("<4I2Q", dfd_off, len(d), kvd_off, len(kv), 0, 0)
    for entry in index:
        out += struct.pack("<3Q", *entry)
    return out + bytes(body)


def pvr_pixel_format(fmt):
    bw, bh, bb, mb, internal, gl_format, vk, code, ch = FORMATS[fmt]
    if code is not None:
        return code
    letters = b"rgba"[:ch]
    v = 0
    for i in range(ch):
        v |= letters[i] << (8 * i) | 8 << (32 + 8 * i)
    return v


def pvr3(fmt, w, h, levels=1, layers=1, faces=1, meta=b"", colour_space=0):
    out = struct.pack("<IIQIIIIIIIII", 0x03525650, 0, pvr_pixel_format(fmt), colour_space, 0, h, w, 1, layers,
                      faces, levels, len(meta)) + meta
    for level in images(fmt, w, h, levels, layers, faces):
        out += b"".join(level)  # per level: surfaces, faces within each
    return out


def main(root):
    seeds = {
        "ktx1": {
            "rgba8_5x3_mips.ktx": ktx1("rgba8", 5, 3, 3),
            "r8_3x2_padded_rows.ktx": ktx1("r8", 3, 2, 2),
            "rgb8_2x2_array3.ktx": ktx1("rgb8", 2, 2, 1, layers=3),
            "etc2_rgb_9x5_mips.ktx": ktx1("etc2_rgb", 9, 5, 4),
            "astc_6x6_7x7_array2.ktx": ktx1("astc_6x6", 7, 7, 3, layers=2),
            "bc5_cube_8.ktx": ktx1("bc5", 8, 8, 2, faces=6),
            "pvrtc1_rgb_4bpp_8x8.ktx": ktx1("pvrtc1_rgb_4bpp", 8, 8, 4),
        },
        "ktx2": {
            "rgba8_5x3_mips.ktx2": ktx2("rgba8", 5, 3, 3),
            "rgb8_3x3_array2.ktx2": ktx2("rgb8", 3, 3, 2, layers=2),
            "eac_r11_9x5_mips.ktx2": ktx2("eac_r11", 9, 5, 4),
            "astc_6x6_cube_6.ktx2": ktx2("astc_6x6", 6, 6, 3, faces=6),
            "bc5_9x8_zstd.ktx2": ktx2("bc5", 9, 8, 4, zstd=True),
            "r8_16x4_zstd.ktx2": ktx2("r8", 16, 4, 5, zstd=True),
        },
        "pvr": {
            "etc2_rgb_9x5_mips.pvr": pvr3("etc2_rgb", 9, 5, 4),
            "rgba8_4x4_metadata.pvr": pvr3("rgba8", 4, 4, 3, meta=b"PVR\x03" + struct.pack("<II", 3, 4) + b"\1\2\3\4"),
            "pvrtc1_rgb_4bpp_8x8_array2.pvr": pvr3("pvrtc1_rgb_4bpp", 8, 8, 2, layers=2),
            "bc5_cube_4.pvr": pvr3("bc5", 4, 4, 3, faces=6),
            "astc_6x6_13x7.pvr": pvr3("astc_6x6", 13, 7, 4),
            "rgb8_3x2.pvr": pvr3("rgb8", 3, 2, 2),
        },
    }
    # Malformed: refused by the readers with a message naming the field.
    good1 = seeds["ktx1"]["rgba8_5x3_mips.ktx"]
    seeds["ktx1"]["bad_big_endian.ktx"] = good1[:12] + struct.pack("<I", 0x01020304) + good1[16:]
    seeds["ktx1"]["bad_image_size.ktx"] = good1[:92] + struct.pack("<I", 64) + good1[96:]
    seeds["ktx1"]["bad_key_value_length.ktx"] = good1[:64] + struct.pack("<I", 999) + good1[68:]
    good2 = seeds["ktx2"]["rgba8_5x3_mips.ktx2"]
    seeds["ktx2"]["bad_level_offset.ktx2"] = good2[:80] + struct.pack("<Q", 65536) + good2[88:]
    z = seeds["ktx2"]["bc5_9x8_zstd.ktx2"]
    seeds["ktx2"]["bad_zstd_length.ktx2"] = z[:96] + struct.pack("<Q", 112) + z[104:]
    seeds["ktx2"]["bad_basislz.ktx2"] = good2[:44] + struct.pack("<I", 1) + good2[48:]
    goodp = seeds["pvr"]["etc2_rgb_9x5_mips.pvr"]
    seeds["pvr"]["bad_srgb.pvr"] = pvr3("etc2_rgb", 9, 5, 4, colour_space=1)
    seeds["pvr"]["bad_metadata_size.pvr"] = goodp[:48] + struct.pack("<I", 4096) + goodp[52:]
    seeds["pvr"]["bad_no_pvr_code.pvr"] = goodp[:8] + struct.pack("<Q", 0xFFFFFFFF) + goodp[16:]  # a fuzz finding
    seeds["pvr"]["bad_swapped_version.pvr"] = struct.pack(">I", 0x03525650) + goodp[4:]
    for folder, files in seeds.items():
        d = root / folder
        d.mkdir(parents=True, exist_ok=True)
        for name, data in files.items():
            assert len(data) < 4096, (name, len(data))
            (d / name).write_bytes(data)
            print(f"{folder}/{name}: {len(data)} bytes")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(Path(sys.argv[1]))
