#!/usr/bin/env python3
"""Writes scenes/gear.obj: a closed, outward-oriented spur gear (genus 1: a bore through it) for the
mesh-edit scene scenes/gears.json. Deterministic; run from the repository root."""
import math
import sys

TEETH, ROOT, TIP, BORE, HALF_HEIGHT = 14, 0.40, 0.50, 0.14, 0.07
PROFILE = [(0.00, ROOT), (0.20, ROOT), (0.35, TIP), (0.65, TIP), (0.80, ROOT)]  # per tooth: (phase, radius)


def rings():
    outer, inner = [], []
    for t in range(TEETH):
        for phase, r in PROFILE:
            a = 2.0 * math.pi * (t + phase) / TEETH
            outer.append((r * math.cos(a), r * math.sin(a)))
            inner.append((BORE * math.cos(a), BORE * math.sin(a)))
    return outer, inner


def mesh():
    outer, inner = rings()
    m = len(outer)
    verts = []
    for ring in (outer, inner):
        for y in (HALF_HEIGHT, -HALF_HEIGHT):
            verts += [(x, y, z) for x, z in ring]
    ot, ob, it, ib = 0, m, 2 * m, 3 * m  # first index of each ring
    tris = []
    for i in range(m):
        j = (i + 1) % m
        tris += [(ot + i, ot + j, ob + j), (ot + i, ob + j, ob + i)]  # outer wall
        tris += [(it + j, it + i, ib + i), (it + j, ib + i, ib + j)]  # bore wall
        tris += [(ot + j, ot + i, it + i), (ot + j, it + i, it + j)]  # top cap
        tris += [(ob + i, ob + j, ib + j), (ob + i, ib + j, ib + i)]  # bottom cap
    return verts, tris


def signed_volume(verts, tris):
    v = 0.0
    for a, b, c in tris:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = verts[a], verts[b], verts[c]
        v += (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0
    return v


def main(path):
    verts, tris = mesh()
    edges = {(t[k], t[(k + 1) % 3]) for t in tris for k in range(3)}
    assert len(edges) == 3 * len(tris) and all((b, a) in edges for a, b in edges), "not closed and consistent"
    if signed_volume(verts, tris) < 0.0:
        tris = [(a, c, b) for a, b, c in tris]
    with open(path, "w") as f:
        f.write(f"# spur gear: {TEETH} teeth, radii {ROOT}-{TIP}, bore {BORE}, height {2 * HALF_HEIGHT} (tools/make_gear_mesh.py)\n")
        f.writelines(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in verts)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in tris)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "scenes/gear.obj")
