#!/usr/bin/python3
"""Generate small, real OpenVDB test volumes plus JSON sidecars with facts
computed by OpenVDB itself (pyopenvdb, C++ OpenVDB 10.0.1 on Debian).

Usage:
    /usr/bin/python3 make_volumes.py OUTDIR [--set shared|extra|tests]

  --set shared   (default) a, b, c + compression / half-float variants
  --set extra    other sizes, offsets (incl. negative index coords),
                 seeds and values, plus d (transformed clouds)
  --set tests    the small set committed in brume's tests/data/volumes: the
                 shared box (leaves and tiles), and a smaller sphere, plume
                 (every compression / half-float variant, negative index
                 origin, translated) and the three transformed clouds

Needs: /usr/bin/python3 with pyopenvdb + numpy (apt: python3-openvdb,
python3-numpy) and /usr/bin/vdb_tool (used for sdfToFogVolume via -ls2fog and
for re-writing files with a chosen compression codec, which pyopenvdb's
write() cannot select).

Conventions recorded in every sidecar (<file>.json):
  * index space is OpenVDB's: voxel (i,j,k) has its *center* at integer index
    coordinates; world = index_to_world @ [i, j, k, 1] (column-vector form).
  * "nearest" sample = value at Coord(floor(x+0.5)) in index space
    (openvdb::tools::PointSampler); "trilinear" = openvdb::tools::BoxSampler
    (floor + trilinear weights over the 8 surrounding voxel values, active or
    not; inactive voxels read as the background).
  * Voxel values and active states come from the OpenVDB accessor of the file
    as re-read from disk (so half-float variants report quantized values).
"""
import argparse
import hashlib
import json
import math
import os
import shutil
import struct
import subprocess
import tempfile

import numpy as np
import pyopenvdb as vdb

VDB_TOOL = shutil.which("vdb_tool") or "/usr/bin/vdb_tool"

# ----------------------------------------------------------------------------
# procedural noise (deterministic, numpy only)
# ----------------------------------------------------------------------------

_M32 = np.uint64(0xFFFFFFFF)


def _hash3(ix, iy, iz, seed):
    """Integer lattice hash -> float in [0,1)."""
    x = ix.astype(np.int64).astype(np.uint64)
    y = iy.astype(np.int64).astype(np.uint64)
    z = iz.astype(np.int64).astype(np.uint64)
    with np.errstate(over="ignore"):
        n = (x * np.uint64(73856093)) ^ (y * np.uint64(19349663)) ^ \
            (z * np.uint64(83492791)) ^ np.uint64((seed * 2654435761) & 0xFFFFFFFF)
        n &= _M32
        n ^= n >> np.uint64(13)
        n = (n * np.uint64(1274126177)) & _M32
        n ^= n >> np.uint64(16)
        n = (n * np.uint64(2246822519)) & _M32
        n ^= n >> np.uint64(15)
    return (n & np.uint64(0xFFFFFF)).astype(np.float64) / float(0x1000000)


def value_noise(p, seed):
    """Smooth value noise in [0,1); p has shape (..., 3)."""
    pf = np.floor(p)
    f = p - pf
    i = pf.astype(np.int64)
    u = f * f * (3.0 - 2.0 * f)
    out = np.zeros(p.shape[:-1])
    for dx in (0, 1):
        wx = u[..., 0] if dx else 1.0 - u[..., 0]
        for dy in (0, 1):
            wy = u[..., 1] if dy else 1.0 - u[..., 1]
            for dz in (0, 1):
                wz = u[..., 2] if dz else 1.0 - u[..., 2]
                out += wx * wy * wz * _hash3(i[..., 0] + dx, i[..., 1] + dy, i[..., 2] + dz, seed)
    return out


def fbm(p, seed, octaves=4, lacunarity=2.03, gain=0.5):
    total, amp, norm = np.zeros(p.shape[:-1]), 1.0, 0.0
    for o in range(octaves):
        total += amp * value_noise(p * (lacunarity ** o), seed + 101 * o)
        norm += amp
        amp *= gain
    return total / norm


def smoothstep(e0, e1, x):
    t = np.clip((x - e0) / (e1 - e0), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def grid_coords(dims):
    nx, ny, nz = dims
    x, y, z = np.meshgrid((np.arange(nx) + 0.5) / nx, (np.arange(ny) + 0.5) / ny,
                          (np.arange(nz) + 0.5) / nz, indexing="ij")
    return x, y, z


# ----------------------------------------------------------------------------
# volume builders
# ----------------------------------------------------------------------------

def make_box(p, tiles):
    """Constant-density box. tiles=False: every voxel set through the
    accessor (leaf nodes only); tiles=True: grid.fill() (OpenVDB stores fully
    covered 8^3 blocks as active Node4-level tiles, no leaves)."""
    g = vdb.FloatGrid(background=0.0)
    g.name = "density"
    g.gridClass = vdb.GridClass.FOG_VOLUME
    g.transform = make_transform(p["transform"])
    lo = p["box_min"]
    hi = [lo[a] + p["box_dims"][a] - 1 for a in range(3)]
    if tiles:
        g.fill(tuple(lo), tuple(hi), float(p["value"]), True)
    else:
        acc = g.getAccessor()
        v = float(p["value"])
        for i in range(lo[0], hi[0] + 1):
            for j in range(lo[1], hi[1] + 1):
                for k in range(lo[2], hi[2] + 1):
                    acc.setValueOn((i, j, k), v)
    return [g]


def make_sphere_fog(p):
    """Level-set sphere (vdb_tool -sphere == tools::createLevelSetSphere)
    converted with vdb_tool -ls2fog (== tools::sdfToFogVolume)."""
    with tempfile.TemporaryDirectory() as td:
        tmp = os.path.join(td, "sphere.vdb")
        c = p["center"]
        cmd = [VDB_TOOL, "-quiet", "-sphere", "voxel=%r" % p["voxel"], "radius=%r" % p["radius"],
               "center=(%r,%r,%r)" % tuple(c), "width=%r" % p["half_width"], "name=sphere_ls",
               "-ls2fog", "name=density", "-write", "codec=blosc", tmp]
        subprocess.run(cmd, check=True)
        grids = vdb.readAll(tmp)[0]
    g = grids[0]
    g.name = "density"
    g.gridClass = vdb.GridClass.FOG_VOLUME
    return [g]


def make_plume(p):
    nx, ny, nz = p["dims"]
    seed = p["seed"]
    x, y, z = grid_coords(p["dims"])
    ph = p.get("phase", 0.0)
    cx = 0.5 + 0.07 * np.sin(2 * np.pi * 1.3 * y + ph)
    cz = 0.5 + 0.07 * np.cos(2 * np.pi * 0.9 * y + 0.5 * ph)
    radius = 0.07 + 0.33 * y                       # cone widening upwards
    dist = np.sqrt((x - cx) ** 2 + (z - cz) ** 2) / radius
    shape = (1.0 - smoothstep(0.55, 1.0, dist)) * smoothstep(0.0, 0.06, y) \
        * (1.0 - smoothstep(0.82, 1.0, y))
    pts = np.stack([x * nx, y * ny - 0.0, z * nz], axis=-1) / p["feature_voxels"]
    n = fbm(pts, seed, octaves=4)
    # billowy: stronger noise where the plume is older (higher)
    density = shape * np.clip(1.6 * n - 0.25 + 0.15 * (1.0 - y), 0.0, None)
    density = np.clip(density, 0.0, 1.0)
    density[density < p["cutoff"]] = 0.0
    temperature = np.where(density > 0.0,
                           np.clip((1.0 - y) * 1.5 * (0.4 + 0.6 * shape) + 0.1 * n, 0.0, None), 0.0)
    temperature[y > p["temp_max_y"]] = 0.0
    out = []
    for name, arr in (("density", density), ("temperature", temperature)):
        g = vdb.FloatGrid(background=0.0)
        g.name = name
        g.gridClass = vdb.GridClass.FOG_VOLUME
        g.transform = make_transform(p["transform"])
        g.copyFromArray(arr.astype(np.float32), ijk=tuple(p["origin"]), tolerance=0.0)
        g.prune()
        out.append(g)
    return out


def make_cloud(p):
    dims = p["dims"]
    x, y, z = grid_coords(dims)
    rng = np.random.default_rng(p["seed"])
    d = np.zeros(x.shape)
    # a few ellipsoidal blobs: a flat base plus billows on top
    blobs = [((0.5, 0.35, 0.5), (0.42, 0.18, 0.38))]
    for _ in range(p["blobs"]):
        c = (rng.uniform(0.25, 0.75), rng.uniform(0.4, 0.65), rng.uniform(0.3, 0.7))
        r = rng.uniform(0.14, 0.24)
        blobs.append((c, (r, r * 1.1, r)))
    for c, r in blobs:
        q = np.sqrt(((x - c[0]) / r[0]) ** 2 + ((y - c[1]) / r[1]) ** 2 + ((z - c[2]) / r[2]) ** 2)
        d = np.maximum(d, 1.0 - q)
    pts = np.stack([x * dims[0], y * dims[1], z * dims[2]], axis=-1) / p["feature_voxels"]
    n = fbm(pts, p["seed"], octaves=5)
    dens = np.clip((d + 0.45 * (n - 0.5)) * 3.0, 0.0, 1.0)
    dens[y < 0.18] = 0.0                            # flat cloud base
    dens[dens < 0.01] = 0.0
    g = vdb.FloatGrid(background=0.0)
    g.name = "density"
    g.gridClass = vdb.GridClass.FOG_VOLUME
    g.transform = make_transform(p["transform"])
    g.copyFromArray(dens.astype(np.float32), ijk=tuple(p["origin"]), tolerance=0.0)
    g.prune()
    return [g]


def make_transform(t):
    """t: {"voxel": s} | {"voxel": s, "translate": [..]} |
          {"voxel_xyz": [sx,sy,sz], "translate": [..]} |
          {"voxel": s, "rotate_deg": [[axis, deg], ...], "translate": [..]}"""
    if "voxel_xyz" in t:
        sx, sy, sz = t["voxel_xyz"]
        tx, ty, tz = t.get("translate", (0, 0, 0))
        m = [[sx, 0, 0, 0], [0, sy, 0, 0], [0, 0, sz, 0], [tx, ty, tz, 1]]
        return vdb.createLinearTransform(m)
    xf = vdb.createLinearTransform(t["voxel"])
    for axis, deg in t.get("rotate_deg", []):
        xf.rotate(math.radians(deg), {"x": vdb.Axis.X, "y": vdb.Axis.Y, "z": vdb.Axis.Z}[axis])
    if "translate" in t:
        xf.translate(tuple(t["translate"]))
    return xf


# ----------------------------------------------------------------------------
# raw header parsing (to report what is really in the file)
# ----------------------------------------------------------------------------

COMPRESSION_BITS = {1: "ZIP", 2: "ACTIVE_MASK", 4: "BLOSC"}


def _rd_str(f):
    (n,) = struct.unpack("<I", f.read(4))
    return f.read(n).decode("latin-1")


def _skip_meta(f):
    (count,) = struct.unpack("<I", f.read(4))
    out = {}
    for _ in range(count):
        name = _rd_str(f)
        typ = _rd_str(f)
        (n,) = struct.unpack("<I", f.read(4))
        data = f.read(n)
        if typ == "bool":
            out[name] = bool(data[0])
    return out


def parse_header(path):
    with open(path, "rb") as f:
        magic, ver, lmaj, lmin, has_off = struct.unpack("<QIIIB", f.read(21))
        if 220 <= ver < 222:
            f.read(1)
        uuid = f.read(36).decode()
        _skip_meta(f)
        (ngrids,) = struct.unpack("<I", f.read(4))
        grids = []
        for _ in range(ngrids):
            name = _rd_str(f)
            typ = _rd_str(f)
            parent = _rd_str(f) if ver >= 216 else ""
            gpos, bpos, epos = struct.unpack("<QQQ", f.read(24))
            f.seek(gpos)
            comp = struct.unpack("<I", f.read(4))[0] if ver >= 222 else None
            meta = _skip_meta(f)
            f.seek(gpos + 4)
            _skip_meta(f)
            map_type = _rd_str(f)
            grids.append({
                "name": name, "type": typ, "instance_parent": parent,
                "compression_flags": comp,
                "compression": [v for b, v in COMPRESSION_BITS.items() if comp and comp & b] or ["NONE"],
                "is_saved_as_half_float": meta.get("is_saved_as_half_float", False),
                "map_type_in_file": map_type,
                "grid_pos": gpos, "block_pos": bpos, "end_pos": epos,
            })
            f.seek(epos)
    return {"file_format_version": ver, "library_version": [lmaj, lmin],
            "has_grid_offsets": bool(has_off), "uuid": uuid, "grids": grids}


# ----------------------------------------------------------------------------
# sidecar facts
# ----------------------------------------------------------------------------

def _f(x):
    return float(x)


def matrix_of(xf):
    o = np.array(xf.indexToWorld((0.0, 0.0, 0.0)))
    cols = [np.array(xf.indexToWorld(e)) - o for e in ((1.0, 0, 0), (0, 1.0, 0), (0, 0, 1.0))]
    m = np.eye(4)
    for c in range(3):
        m[:3, c] = cols[c]
    m[:3, 3] = o
    return m


def trilinear(acc, xyz):
    i0 = [math.floor(c) for c in xyz]
    u = [xyz[a] - i0[a] for a in range(3)]
    v = 0.0
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                w = (u[0] if dx else 1 - u[0]) * (u[1] if dy else 1 - u[1]) * (u[2] if dz else 1 - u[2])
                v += w * acc.getValue((i0[0] + dx, i0[1] + dy, i0[2] + dz))
    return v


def sample_points(g, rng, n_random=10):
    """Index-space points to probe: bbox centre, active-voxel centres with
    and without fractional offsets, inactive/outside points."""
    lo, hi = g.evalActiveVoxelBoundingBox()
    lo, hi = np.array(lo, float), np.array(hi, float)
    pts = [("bbox_center", (lo + hi) / 2.0)]
    leaf_vox = [it.min for it in g.citerOnValues() if it.count == 1]
    tiles = [(it.min, it.max) for it in g.citerOnValues() if it.count > 1]
    if leaf_vox:
        sel = rng.choice(len(leaf_vox), size=min(n_random, len(leaf_vox)), replace=False)
        for s in sel[: n_random // 2]:
            pts.append(("active_voxel_center", np.array(leaf_vox[s], float)))
        for s in sel[n_random // 2:]:
            pts.append(("near_active_voxel", np.array(leaf_vox[s], float) + rng.uniform(-0.5, 0.5, 3)))
    for (tmin, tmax) in tiles[:2]:
        c = (np.array(tmin, float) + np.array(tmax, float)) / 2.0 + rng.uniform(-0.5, 0.5, 3)
        pts.append(("inside_active_tile", c))
    pts.append(("bbox_min_corner_voxel", lo.copy()))
    pts.append(("outside_bbox", hi + np.array([5.25, 3.5, 7.75])))
    pts.append(("random_in_bbox", lo + rng.uniform(0, 1, 3) * (hi - lo)))
    return pts


def grid_facts(g, rng, extra_points=()):
    xf = g.transform
    acc = g.getConstAccessor()
    lo, hi = g.evalActiveVoxelBoundingBox()
    vmin, vmax = g.evalMinMax()
    n_tiles, tile_vox, sum_active, leaf_vox_count = 0, 0, 0.0, 0
    tile_depths = {}
    for it in g.citerOnValues():
        sum_active += float(it.value) * it.count
        if it.count > 1:
            n_tiles += 1
            tile_vox += it.count
            tile_depths[str(it.depth)] = tile_depths.get(str(it.depth), 0) + 1
        else:
            leaf_vox_count += 1

    def world_box(a, b):
        cs = [xf.indexToWorld((x, y, z)) for x in (a[0], b[0]) for y in (a[1], b[1]) for z in (a[2], b[2])]
        cs = np.array(cs)
        return {"min": cs.min(0).tolist(), "max": cs.max(0).tolist()}

    samples = []
    for label, ip in list(sample_points(g, rng)) + [(l, np.array(xf.worldToIndex(tuple(w)))) for l, w in extra_points]:
        world = xf.indexToWorld(tuple(float(c) for c in ip))
        idx = xf.worldToIndex(world)        # what a reader must reproduce
        near = tuple(int(math.floor(c + 0.5)) for c in idx)
        val, active = acc.probeValue(near)
        samples.append({
            "label": label,
            "world": [_f(c) for c in world],
            "index": [_f(c) for c in idx],
            "nearest_ijk": list(near),
            "nearest_value": _f(val),
            "nearest_active": bool(active),
            "trilinear_value": _f(trilinear(acc, idx)),
        })
    # direct voxel probes (tests tree decoding without any transform)
    probes = []
    leaf_vox = [it.min for it in g.citerOnValues() if it.count == 1]
    if leaf_vox:
        for s in rng.choice(len(leaf_vox), size=min(8, len(leaf_vox)), replace=False):
            ijk = tuple(int(c) for c in leaf_vox[s])
            v, a = acc.probeValue(ijk)
            probes.append({"ijk": list(ijk), "value": _f(v), "active": bool(a)})
    for ijk in (tuple(int(c) for c in lo), tuple(int(c) for c in hi),
                tuple(int(c) - 1 for c in lo), (int(hi[0]) + 9, int(lo[1]), int(lo[2]))):
        v, a = acc.probeValue(ijk)
        probes.append({"ijk": list(ijk), "value": _f(v), "active": bool(a)})

    meta = {}
    for k in g.metadata.keys() if hasattr(g.metadata, "keys") else []:
        val = g.metadata[k]
        if isinstance(val, (bool, int, float, str)):
            meta[k] = val
        elif isinstance(val, (tuple, list)):
            meta[k] = list(val)
    return {
        "name": g.name,
        "value_type": g.valueTypeName,
        "grid_class": str(g.gridClass),
        "background": _f(g.background),
        "save_float_as_half": bool(g.saveFloatAsHalf),
        "transform": {
            "map_type": xf.typeName,
            "voxel_size": [_f(c) for c in xf.voxelSize()],
            "index_to_world": matrix_of(xf).tolist(),
            "index_to_world_note": "world = M @ [i,j,k,1]; voxel centres at integer ijk",
        },
        "active_voxel_count": int(g.activeVoxelCount()),
        "active_leaf_voxel_count": int(g.activeLeafVoxelCount()),
        "active_tile_count": n_tiles,
        "active_tile_voxel_count": tile_vox,
        "active_tiles_by_depth": tile_depths,
        "tile_depth_note": "depth 1 = tile in Node5 (128^3 voxels), 2 = tile in Node4 (8^3), 0 = root tile",
        "leaf_count": int(g.leafCount()),
        "non_leaf_count": int(g.nonLeafCount()),
        "min_value": _f(vmin),
        "max_value": _f(vmax),
        "sum_active_values": sum_active,
        "index_bbox_active": {"min": list(lo), "max": list(hi)},
        "world_bbox_voxel_centers": world_box(lo, hi),
        "world_bbox_cell_extent": world_box([c - 0.5 for c in lo], [c + 0.5 for c in hi]),
        "metadata": meta,
        "samples": samples,
        "voxel_probes": probes,
    }


def write_sidecar(path, spec, seed):
    rng = np.random.default_rng(seed)
    grids = vdb.readAll(path)[0]
    st = os.stat(path)
    with open(path, "rb") as fh:
        sha = hashlib.sha256(fh.read()).hexdigest()
    side = {
        "file": os.path.basename(path),
        "size_bytes": st.st_size,
        "sha256": sha,
        "written_by": "OpenVDB %s via pyopenvdb / vdb_tool (make_volumes.py)" % ".".join(map(str, vdb.LIBRARY_VERSION)),
        "description": spec.get("description", ""),
        "generator_params": spec.get("params", {}),
        "file_header": parse_header(path),
        "grid_names": [g.name for g in grids],
        "grids": [grid_facts(g, rng, spec.get("extra_points", ())) for g in grids],
    }
    side.update(spec.get("analytic", {}))
    with open(path + ".json", "w") as fh:
        json.dump(side, fh, indent=1)
    return side


# ----------------------------------------------------------------------------
# writing
# ----------------------------------------------------------------------------

def write_vdb(path, grids, codec=None, half=False, file_meta=None):
    """Write with pyopenvdb (default codec: BLOSC|ACTIVE_MASK in this build),
    or re-write through vdb_tool when an explicit codec is requested.

    OpenVDB's Archive::setGridCompression silently drops COMPRESS_ZIP for
    grids whose class is LEVEL_SET or FOG_VOLUME, so ZIP variants are written
    with grid class UNKNOWN (otherwise they would be ACTIVE_MASK-only)."""
    for g in grids:
        g.saveFloatAsHalf = bool(half)
        if codec == "zip":
            g.gridClass = vdb.GridClass.UNKNOWN
    if codec is None:
        vdb.write(path, grids=grids, metadata=file_meta or {})
        return
    with tempfile.TemporaryDirectory() as td:
        tmp = os.path.join(td, "in.vdb")
        vdb.write(tmp, grids=grids, metadata=file_meta or {})
        cmd = [VDB_TOOL, "-quiet", "-read", tmp, "-write", "codec=%s" % codec,
               "bits=%d" % (16 if half else 32), path]
        subprocess.run(cmd, check=True)
    # NB: vdb_tool pushes grids on a stack, so grid order in the file is
    # reversed w.r.t. `grids` (readers should look grids up by name).


# ----------------------------------------------------------------------------
# parameter sets
# ----------------------------------------------------------------------------

def params(which):
    if which == "shared":
        return {
            "seed": 1,
            "box": {"transform": {"voxel": 1.0 / 32.0}, "box_min": [0, 0, 0],
                    "box_dims": [32, 32, 32], "value": 1.0},
            "sphere": {"voxel": 0.025, "radius": 1.0, "center": [0.0, 0.0, 0.0], "half_width": 3.0},
            "plume": {"dims": [96, 96, 96], "origin": [0, 0, 0], "seed": 1, "phase": 0.0,
                      "feature_voxels": 14.0, "cutoff": 0.02, "temp_max_y": 0.7,
                      "transform": {"voxel": 0.02}},
            "cloud": None,
        }
    if which == "tests":
        # small enough to commit: every variant of the shared and extra sets
        # at a fraction of their size (the 96^3 plume ships in volumes/); the
        # plume stays inside one root child, as an uncompressed file stores
        # every internal node densely (128 KiB per 4096^3 node)
        return {
            "seed": 5,
            "box": {"transform": {"voxel": 1.0 / 32.0}, "box_min": [0, 0, 0],
                    "box_dims": [32, 32, 32], "value": 1.0},
            "sphere": {"voxel": 0.05, "radius": 1.0, "center": [0.1, -0.2, 0.05], "half_width": 3.0},
            "plume": {"dims": [24, 32, 24], "origin": [-36, 3, -30], "seed": 5, "phase": 0.3,
                      "feature_voxels": 5.0, "cutoff": 0.025, "temp_max_y": 0.65,
                      "transform": {"voxel": 0.06, "translate": [0.25, -0.5, 0.75]}},
            "cloud": {"dims": [32, 20, 28], "origin": [-10, 3, -14], "seed": 5, "blobs": 4,
                      "feature_voxels": 5.0},
        }
    # "extra": other sizes, offsets (negative index coordinates), seeds and
    # transforms (rotated, translated, anisotropic) for wider tests.
    return {
        "seed": 3,
        "box": {"transform": {"voxel": 0.05, "translate": [-0.4, 0.1, 0.2]},
                "box_min": [-20, -8, 3], "box_dims": [20, 28, 36], "value": 0.5},
        "sphere": {"voxel": 0.02, "radius": 0.9, "center": [0.1, -0.3, 0.2], "half_width": 3.0},
        "plume": {"dims": [72, 96, 64], "origin": [-30, 4, -12], "seed": 3, "phase": 0.6,
                  "feature_voxels": 12.0, "cutoff": 0.025, "temp_max_y": 0.6,
                  "transform": {"voxel": 0.03, "translate": [0.5, -0.25, 1.0]}},
        "cloud": {"dims": [64, 40, 56], "origin": [-20, 6, -28], "seed": 3, "blobs": 5,
                  "feature_voxels": 8.0},
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir")
    ap.add_argument("--set", choices=["shared", "extra", "tests"], default="shared")
    args = ap.parse_args()
    P = params(args.set)
    os.makedirs(args.outdir, exist_ok=True)
    out = lambda n: os.path.join(args.outdir, n)
    made = []

    def emit(name, grids, spec, codec=None, half=False):
        path = out(name)
        write_vdb(path, grids, codec=codec, half=half)
        side = write_sidecar(path, spec, P["seed"] + len(made))
        made.append((name, side["size_bytes"]))
        print("wrote %-34s %9d bytes  grids=%s" % (name, side["size_bytes"], side["grid_names"]))

    # a. homogeneous box -----------------------------------------------------
    bp = P["box"]
    vs = bp["transform"]["voxel"]
    lo = np.array(bp["box_min"], float)
    dims = np.array(bp["box_dims"], float)
    xf = make_transform(bp["transform"])
    centre_w = xf.indexToWorld(tuple(lo + (dims - 1) / 2.0))
    box_analytic = {"analytic": {
        "density_inside": bp["value"],
        "box_index_min": bp["box_min"], "box_index_dims": bp["box_dims"],
        "optical_depth_axis_rays_through_centre": {
            ax: bp["value"] * dims[i] * vs for i, ax in enumerate("xyz")},
        "optical_depth_note": "integral of density along a world axis-aligned ray through the box "
                              "interior = value*dims*voxel for nearest (cell) AND trilinear lookups; "
                              "transmittance = exp(-sigma_t_scale * that)",
        "box_world_centre": list(centre_w)}}
    for tiles, name in ((False, "homogeneous_box.vdb"), (True, "homogeneous_box_tiles.vdb")):
        spec = {"description": "constant %g in a %s box, %s" % (
            bp["value"], "x".join(map(str, bp["box_dims"])),
            "stored as active Node4 tiles (grid.fill), no leaves" if tiles else "stored as leaf voxels"),
            "params": bp}
        spec.update(box_analytic)
        hi_i = lo + dims - 1
        mid = lo + (dims - 1) / 2.0
        edge = lambda a, off: tuple(np.where(np.arange(3) == a, off, mid))
        spec["extra_points"] = [("box_world_centre", centre_w),
                                # trilinear ramps across the box faces: 0.75, 0.25, 0.5, 0.25
                                ("face_ramp_0.75", xf.indexToWorld(edge(2, hi_i[2] + 0.25))),
                                ("face_ramp_0.25", xf.indexToWorld(edge(2, hi_i[2] + 0.75))),
                                ("face_ramp_0.5", xf.indexToWorld(edge(1, lo[1] - 0.5))),
                                ("face_ramp_0.25b", xf.indexToWorld(edge(0, lo[0] - 0.75)))]
        emit(name, make_box(bp, tiles), spec)

    # b. sphere fog ----------------------------------------------------------
    sp = P["sphere"]
    emit("sphere_fog.vdb", make_sphere_fog(sp), {
        "description": "level-set sphere (createLevelSetSphere) -> sdfToFogVolume (vdb_tool -ls2fog); "
                       "interior = active tiles of 1.0, inner half of narrow band ramps 0..1",
        "params": sp, "extra_points": [("sphere_centre", sp["center"])],
        "analytic": {"analytic": {"sphere_center_world": sp["center"], "sphere_radius_world": sp["radius"],
                                  "density_at_center": 1.0}}})

    # c. smoke plume + compression / half variants ----------------------------
    pp = P["plume"]
    plume_spec = {"description": "procedural rising smoke plume (fbm value noise in a widening cone), "
                                 "grids 'density' (0..1) and 'temperature'", "params": pp}
    variants = [("smoke_plume.vdb", None, False, "default pyopenvdb write (BLOSC|ACTIVE_MASK)"),
                ("smoke_plume_zip.vdb", "zip", False, "ZIP|ACTIVE_MASK (vdb_tool codec=zip; grid class UNKNOWN because OpenVDB drops ZIP for fog volumes)"),
                ("smoke_plume_none.vdb", "none", False, "no compression at all (codec=none)"),
                ("smoke_plume_activemask.vdb", "active", False, "ACTIVE_MASK only (codec=active)"),
                ("smoke_plume_half.vdb", None, True, "saveFloatAsHalf=True, default BLOSC|ACTIVE_MASK"),
                ("smoke_plume_half_zip.vdb", "zip", True, "saveFloatAsHalf (bits=16), ZIP|ACTIVE_MASK, grid class UNKNOWN"),
                ("smoke_plume_half_none.vdb", "none", True, "saveFloatAsHalf (bits=16), no compression")]
    for name, codec, half, desc in variants:
        spec = dict(plume_spec)
        spec["description"] = plume_spec["description"] + "; " + desc
        emit(name, make_plume(pp), spec, codec=codec, half=half)

    # d. transformed clouds (extra set only) ----------------------------------
    cp = P["cloud"]
    cv = 0.08 if args.set == "tests" else 0.04
    if cp:
        for name, t, desc in (
                ("cloud_transformed.vdb",
                 {"voxel": cv, "rotate_deg": [["x", 20.0], ["z", -35.0]], "translate": [-1.5, 0.5, 2.0]},
                 "voxel %g, rotated 20deg about X then -35deg about Z, translated -> AffineMap" % cv),
                ("cloud_translated.vdb", {"voxel": cv, "translate": [-1.5, 0.5, 2.0]},
                 "voxel %g, translated -> UniformScaleTranslateMap" % cv),
                ("cloud_anisotropic.vdb", {"voxel_xyz": [0.02, 0.06, 0.04], "translate": [0.75, -0.5, 1.25]},
                 "non-uniform voxel (0.02,0.06,0.04), translated -> ScaleTranslateMap")):
            c = dict(cp)
            c["transform"] = t
            emit(name, make_cloud(c), {"description": "cumulus-like cloud (ellipsoid blobs eroded by fbm); " + desc,
                                       "params": c})
    with open(out("MANIFEST.json"), "w") as fh:
        json.dump({"set": args.set, "generator": "make_volumes.py",
                   "files": [{"file": n, "size_bytes": s, "sidecar": n + ".json"} for n, s in made]}, fh, indent=1)


if __name__ == "__main__":
    main()
