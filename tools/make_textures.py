#!/usr/bin/env python3
"""Writes the small test textures of tests/data/textures/ (standard library only).

    python3 tools/make_textures.py

checker4x2.png: 4 x 2 texels, 8-bit sRGB RGB, every channel of every texel a
different byte, so that a render of it shows any swapped axis, flipped row or
skipped sRGB decode. The bytes are listed in TEXELS (row 0 = top row of the file).
"""
import os
import struct
import zlib

TEXELS = [
    [(200, 40, 90), (30, 220, 140), (120, 60, 250), (250, 180, 20)],
    [(10, 100, 200), (160, 250, 60), (90, 10, 30), (230, 130, 170)],
]


def chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


def write_png(path, rows):
    height, width = len(rows), len(rows[0])
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in rows)
    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


if __name__ == "__main__":
    out = os.path.join(os.path.dirname(__file__), "..", "tests", "data", "textures")
    os.makedirs(out, exist_ok=True)
    write_png(os.path.join(out, "checker4x2.png"), TEXELS)
