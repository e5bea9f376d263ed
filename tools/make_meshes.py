#!/usr/bin/env python3
"""Writes the closed OBJ meshes of the shape-interior tests and the
smoke-in-a-glass gallery scene (deterministic; standard library only):

    python3 tools/make_meshes.py

tests/data/meshes/cube.obj       the cube [-1, 1]^3, 12 triangles, wound outward
tests/data/meshes/open_box.obj   the cube without one face (not closed)
tests/data/meshes/u_shape.obj    a U of seven unit voxels (concave: a ray can
                                 enter, leave and enter again), wound outward
scenes/glass_cup.obj             a thick-walled cup (radius 0.5, height 1, wall
                                 0.04, base 0.08), revolved from its profile
scenes/glass_cup_cavity.obj      the air inside the cup, 2 mm clear of the glass,
                                 up to the rim (the smoke's bounds)

Every mesh is closed and consistently wound counter-clockwise seen from
outside (brume checks both on load, and the signed volume printed here is
positive).
"""
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def signed_volume(verts, tris):
    v = 0.0
    for a, b, c in tris:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = verts[a], verts[b], verts[c]
        v += (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0
    return v


def write(path, verts, tris, comment):
    vol = signed_volume(verts, tris)
    assert vol > 0 or "open" in path, f"{path}: wound inward (volume {vol})"
    with open(os.path.join(ROOT, path), "w") as f:
        f.write(f"# {comment}\n# written by tools/make_meshes.py; {len(tris)} triangles, volume {vol:.6f}\n")
        for x, y, z in verts:
            f.write(f"v {x:.6f} {y:.6f} {z:.6f}\n")
        for a, b, c in tris:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")
    print(f"{path}: {len(verts)} vertices, {len(tris)} triangles, volume {vol:.6f}")


def voxels(cells):
    """The boundary of a set of unit cells, two triangles per exposed face."""
    index = {}
    verts, tris = [], []

    def vid(p):
        if p not in index:
            index[p] = len(verts)
            verts.append(p)
        return index[p]

    cells = set(cells)
    for (x, y, z) in sorted(cells):
        for axis in range(3):
            for sign in (-1, 1):
                n = [0, 0, 0]
                n[axis] = sign
                if (x + n[0], y + n[1], z + n[2]) in cells:
                    continue
                # the face's corners, counter-clockwise seen along +n
                u, w = (axis + 1) % 3, (axis + 2) % 3
                base = [x, y, z]
                if sign > 0:
                    base[axis] += 1
                corners = []
                for du, dw in ((0, 0), (1, 0), (1, 1), (0, 1)):
                    p = list(base)
                    p[u] += du
                    p[w] += dw
                    corners.append(tuple(float(c) for c in p))
                if sign < 0:
                    corners.reverse()
                q = [vid(c) for c in corners]
                tris += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    return verts, tris


def revolve(profile, segments):
    """Revolves a closed (r, y) profile about +Y; points with r = 0 stay single vertices.

    The winding is made outward from the sign of the volume.
    """
    verts, tris = [], []
    rings = []
    for r, y in profile:
        if r == 0.0:
            rings.append([len(verts)] * segments)
            verts.append((0.0, y, 0.0))
        else:
            ring = []
            for j in range(segments):
                phi = 2.0 * math.pi * j / segments
                ring.append(len(verts))
                verts.append((r * math.cos(phi), y, -r * math.sin(phi)))
            rings.append(ring)
    n = len(profile)
    for i in range(n):
        a, b = rings[i], rings[(i + 1) % n]
        if profile[i][0] == 0.0 and profile[(i + 1) % n][0] == 0.0:
            continue  # along the axis: no surface
        for j in range(segments):
            k = (j + 1) % segments
            quad = [a[j], a[k], b[k], b[j]]
            for t in ((quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])):
                if len(set(t)) == 3:
                    tris.append(t)
    if signed_volume(verts, tris) < 0:
        tris = [(a, c, b) for a, b, c in tris]
    return verts, tris


def main():
    c = lambda x, y, z: (x, y, z)
    cube_v = [c(-1.0 + 2.0 * (i & 1), -1.0 + (i & 2), -1.0 + 0.5 * (i & 4)) for i in range(8)]
    cube_t = []
    for q in ((0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)):
        cube_t += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    write("tests/data/meshes/cube.obj", cube_v, cube_t, "the cube [-1, 1]^3")
    write("tests/data/meshes/open_box.obj", cube_v, cube_t[:-2],
          "the cube [-1, 1]^3 without its +x face: not closed (refused as a shape interior)")

    u_cells = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 1, 0), (0, 2, 0), (2, 1, 0), (2, 2, 0)]
    v, t = voxels(u_cells)
    write("tests/data/meshes/u_shape.obj", v, t,
          "a U of unit voxels: x in [0, 3], y in [0, 3], z in [0, 1], open slot x in [1, 2], y in [1, 3]")

    radius, height, wall, base, segments = 0.5, 1.0, 0.04, 0.08, 96
    cup = [(0.0, 0.0), (radius, 0.0), (radius, height), (radius - wall, height),
           (radius - wall, base), (0.0, base)]
    v, t = revolve(cup, segments)
    write("scenes/glass_cup.obj", v, t, "a thick-walled glass cup: radius 0.5, height 1, wall 0.04, base 0.08")
    gap = 0.002
    cavity = [(0.0, base + gap), (radius - wall - gap, base + gap), (radius - wall - gap, height), (0.0, height)]
    v, t = revolve(cavity, segments)
    write("scenes/glass_cup_cavity.obj", v, t, "the air inside glass_cup.obj, 2 mm clear of the glass, up to the rim")


if __name__ == "__main__":
    sys.exit(main())
