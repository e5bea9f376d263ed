"""A small OpenEXR reader for the benchmark tools: scan-line files, NONE / RLE /
ZIPS / ZIP compression, half / float / uint channels, into a numpy array.

Written from the OpenEXR file-layout documentation ("The OpenEXR File
Layout" and "Technical Introduction"), so the harnesses need no third-party
EXR module: brume writes ZIP scan lines of half floats, Cycles (through
bpy) ZIP scan lines of 32-bit floats.

    from exr_numpy import read_rgb
    image = read_rgb("out.exr")       # (height, width, 3) float32, linear
"""

import struct
import zlib

import numpy as np

# Compression codes of the `compression` attribute and the scan lines per chunk.
LINES_PER_CHUNK = {0: 1, 1: 1, 2: 1, 3: 16}
PIXEL_TYPES = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}


def _header(data):
    """The header attributes (name → (type, raw bytes)) and the offset after it."""
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("not an OpenEXR file (magic number missing)")
    flags = struct.unpack_from("<I", data, 4)[0]
    if flags & 0x200 or flags & 0x1000 or flags & 0x800:
        raise ValueError("tiled, deep or multi-part EXR: only single-part scan lines are read")
    pos, attrs = 8, {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        tend = data.index(b"\0", end + 1)
        kind = data[end + 1:tend].decode()
        size = struct.unpack_from("<i", data, tend + 1)[0]
        attrs[name] = (kind, data[tend + 5:tend + 5 + size])
        pos = tend + 5 + size
    return attrs, pos + 1


def _channels(raw):
    """(name, pixel type) of each channel of a `chlist`, in file (alphabetical) order."""
    out, pos = [], 0
    while raw[pos] != 0:
        end = raw.index(b"\0", pos)
        name = raw[pos:end].decode()
        # pixel type (int), pLinear (uchar), 3 reserved bytes, x and y sampling (ints).
        ptype = struct.unpack_from("<i", raw, end + 1)[0]
        xs, ys = struct.unpack_from("<ii", raw, end + 9)
        if xs != 1 or ys != 1:
            raise ValueError(f"channel {name} is subsampled: not supported")
        out.append((name, ptype))
        pos = end + 17
    return out


def _unrle(buf):
    """OpenEXR's run-length decoding (signed count byte: runs and literals)."""
    out = bytearray()
    i = 0
    while i < len(buf):
        n = struct.unpack_from("b", buf, i)[0]
        i += 1
        if n < 0:
            out += buf[i:i - n]
            i -= n
        else:
            out += bytes([buf[i]]) * (n + 1)
            i += 1
    return bytes(out)


def _unpredict(buf):
    """Undoes the byte predictor and the split into even and odd bytes (ZIP and RLE)."""
    d = np.frombuffer(buf, dtype=np.uint8).astype(np.int64)
    if len(d) == 0:
        return b""
    # t[0] = d[0], t[i] = t[i-1] + d[i] - 128 (mod 256).
    d[1:] -= 128
    t = (np.cumsum(d) % 256).astype(np.uint8)
    half = (len(t) + 1) // 2
    out = np.empty(len(t), dtype=np.uint8)
    out[0::2] = t[:half]
    out[1::2] = t[half:]
    return out.tobytes()


def _decode(chunk, compression, expected):
    if len(chunk) == expected or compression == 0:
        return chunk
    if compression in (2, 3):
        return _unpredict(zlib.decompress(chunk))
    if compression == 1:
        return _unpredict(_unrle(chunk))
    raise ValueError(f"EXR compression {compression} is not supported by tools/exr_numpy.py")


def read_channels(path):
    """Every channel of a scan-line EXR as float32 arrays (height, width), by name."""
    data = open(path, "rb").read()
    attrs, pos = _header(data)
    channels = _channels(attrs["channels"][1])
    compression = attrs["compression"][1][0]
    if compression not in LINES_PER_CHUNK:
        raise ValueError(f"{path}: EXR compression {compression} is not supported")
    x0, y0, x1, y1 = struct.unpack("<iiii", attrs["dataWindow"][1])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    per = LINES_PER_CHUNK[compression]
    chunks = (height + per - 1) // per
    offsets = struct.unpack_from(f"<{chunks}Q", data, pos)
    planes = {name: np.empty((height, width), np.float32) for name, _ in channels}
    row_bytes = sum(PIXEL_TYPES[t].itemsize for _, t in channels) * width
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        lines = min(per, y1 + 1 - y)
        raw = _decode(data[off + 8:off + 8 + size], compression, row_bytes * lines)
        at = 0
        for line in range(lines):
            for name, t in channels:
                dt = PIXEL_TYPES[t]
                n = dt.itemsize * width
                planes[name][y - y0 + line] = np.frombuffer(raw[at:at + n], dtype=dt).astype(np.float32)
                at += n
    return planes


def read_rgb(path):
    """The R, G, B channels of a scan-line EXR as one (height, width, 3) float32 array."""
    planes = read_channels(path)
    missing = [c for c in "RGB" if c not in planes]
    if missing:
        raise ValueError(f"{path}: no {','.join(missing)} channel")
    return np.stack([planes["R"], planes["G"], planes["B"]], axis=-1)
