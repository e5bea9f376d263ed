#!/usr/bin/python3
"""Generate the animated test plume: frames plume.0001.vdb .. plume.0003.vdb,
each with a float grid `density` and a vec3s grid `vel` (world units per
second, as Houdini and Blender write velocity), plus a JSON sidecar per file
with facts computed by OpenVDB itself (pyopenvdb, OpenVDB 10.0.1 on Debian).

Usage: /usr/bin/python3 make_anim_plume.py OUTDIR
Needs: apt-get install -y python3-openvdb python3-numpy

Sidecar conventions (as shared/tools/make_volumes.py): voxel (i,j,k) has its
centre at integer index coordinates; "trilinear" is openvdb::tools::BoxSampler
(floor + trilinear weights over the 8 surrounding voxel values, active or
not, inactive voxels read as stored); values come from the accessor of the
file as re-read from disk (so the half-float file reports quantized values).
Vec3 values are listed per component.
"""
import json
import math
import os
import sys

import numpy as np
import pyopenvdb as vdb

DIMS = (20, 24, 20)
ORIGIN = (-10, 0, -10)
VOXEL = 0.05
FPS = 24.0


def fields(frame):
    """Density and velocity of the plume at `frame`: a soft column rising at
    RISE m/s with a swirl about the y axis; the density pattern is advected
    by the same velocity from frame to frame."""
    i, j, k = np.meshgrid(*(np.arange(d) + o for d, o in zip(DIMS, ORIGIN)), indexing="ij")
    x, y, z = i * VOXEL, j * VOXEL, k * VOXEL
    rise, spin = 0.6, 1.5                        # m/s, rad/s
    t = (frame - 1) / FPS
    r = np.sqrt(x * x + z * z)
    yy = y - rise * t
    radius = 0.12 + 0.25 * np.clip(y / (DIMS[1] * VOXEL), 0, 1)
    bumps = 0.5 + 0.5 * np.sin(9.0 * yy + 3.0 * np.arctan2(z, x) - spin * t * 3.0)
    density = np.clip(1.0 - r / radius, 0.0, None) * (0.4 + 0.6 * bumps)
    density[density < 0.02] = 0.0
    vel = np.stack([-spin * z, np.full_like(x, rise), spin * x], axis=-1)
    vel[density == 0.0] = 0.0
    return density.astype(np.float32), vel.astype(np.float32)


def grids_for(frame, half=False):
    density, vel = fields(frame)
    xf = vdb.createLinearTransform(VOXEL)
    d = vdb.FloatGrid(background=0.0)
    d.name, d.gridClass, d.transform = "density", vdb.GridClass.FOG_VOLUME, xf
    d.copyFromArray(density, ijk=ORIGIN, tolerance=0.0)
    v = vdb.Vec3SGrid(background=(0.0, 0.0, 0.0))
    v.name, v.transform = "vel", xf.deepCopy()
    v.vectorType = vdb.VectorType.CONTRAVARIANT_RELATIVE
    v.copyFromArray(vel, ijk=ORIGIN, tolerance=(0.0, 0.0, 0.0))
    d.prune(0.0)
    v.prune((0.0, 0.0, 0.0))
    for g in (d, v):
        g.saveFloatAsHalf = half
    return [d, v]


def as_list(value):
    return [float(c) for c in value] if isinstance(value, tuple) else [float(value)]


def trilinear(acc, idx):
    i0 = [math.floor(c) for c in idx]
    u = [idx[a] - i0[a] for a in range(3)]
    total = None
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                w = (u[0] if dx else 1 - u[0]) * (u[1] if dy else 1 - u[1]) * (u[2] if dz else 1 - u[2])
                val = np.array(as_list(acc.getValue((i0[0] + dx, i0[1] + dy, i0[2] + dz))))
                total = w * val if total is None else total + w * val
    return total.tolist()


def facts(g, rng):
    acc = g.getConstAccessor()
    xf = g.transform
    lo, hi = g.evalActiveVoxelBoundingBox()
    active = [as_list(it.value) for it in g.citerOnValues() for _ in range(it.count)]
    arr = np.array(active)
    world_points = [xf.indexToWorld(tuple(float(c) for c in np.array(lo) + rng.uniform(-1, 1, 3)
                                          + rng.uniform(0, 1, 3) * (np.array(hi) - np.array(lo))))
                    for _ in range(12)]
    samples = []
    for w in world_points:
        idx = xf.worldToIndex(w)
        samples.append({"world": list(w), "index": list(idx), "trilinear_value": trilinear(acc, idx)})
    probes = []
    for _ in range(12):
        ijk = tuple(int(c) for c in rng.integers(np.array(lo) - 1, np.array(hi) + 2))
        val, on = acc.probeValue(ijk)
        probes.append({"ijk": list(ijk), "value": as_list(val), "active": bool(on)})
    return {
        "name": g.name,
        "value_type": g.valueTypeName,
        "background": as_list(g.background),
        "voxel_size": list(xf.voxelSize()),
        "active_voxel_count": int(g.activeVoxelCount()),
        "leaf_count": int(g.leafCount()),
        "index_bbox_active": {"min": list(lo), "max": list(hi)},
        "component_min": arr.min(0).tolist(),
        "component_max": arr.max(0).tolist(),
        "max_magnitude": float(np.sqrt((arr * arr).sum(1)).max()),
        "samples": samples,
        "voxel_probes": probes,
    }


def write(path, grids, seed):
    vdb.write(path, grids=grids)
    rng = np.random.default_rng(seed)
    read = vdb.readAll(path)[0]
    side = {
        "file": os.path.basename(path),
        "size_bytes": os.stat(path).st_size,
        "written_by": "OpenVDB %s via pyopenvdb (make_anim_plume.py)" % ".".join(map(str, vdb.LIBRARY_VERSION)),
        "frames_per_second": FPS,
        "grids": [facts(g, rng) for g in sorted(read, key=lambda g: g.name)],
    }
    with open(path + ".json", "w") as fh:
        json.dump(side, fh, indent=1)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    for frame in (1, 2, 3):
        write(os.path.join(out, "plume.%04d.vdb" % frame), grids_for(frame), seed=frame)
    write(os.path.join(out, "plume_half.vdb"), grids_for(1, half=True), seed=7)


if __name__ == "__main__":
    main()
