#!/usr/bin/env python3
"""Writes a closed tube around a (2, 3) torus knot as OBJ: every edge shared by two triangles,
genus 1, U x V quads split into 2 U V triangles (the default 400 x 24: 19,200 triangles).

  tools/make_knot_mesh.py OUT.obj [--winding outward|inward|mixed] [--u 400] [--v 24]

--winding inward reverses every triangle (as many exported files are); mixed reverses every third
one. sdfbrick orients all three to the same mesh (docs/mesh.md#orientation). Deterministic."""
import argparse
import math


def knot(t):
    """Point of the (2, 3) torus knot at parameter t in [0, 2 pi)."""
    r = 0.5 + 0.2 * math.cos(3.0 * t)
    return (r * math.cos(2.0 * t), 0.2 * math.sin(3.0 * t), r * math.sin(2.0 * t))


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    n = math.sqrt(sum(x * x for x in a))
    return tuple(x / n for x in a)


def mesh(u_count, v_count, radius=0.07):
    verts = []
    for i in range(u_count):
        t = 2.0 * math.pi * i / u_count
        c = knot(t)
        tangent = unit(sub(knot(t + 1e-4), knot(t - 1e-4)))
        normal = unit(cross(tangent, (0.0, 1.0, 0.0)))
        binormal = cross(tangent, normal)
        for j in range(v_count):
            a = 2.0 * math.pi * j / v_count
            verts.append(tuple(c[k] + radius * (math.cos(a) * normal[k] + math.sin(a) * binormal[k]) for k in range(3)))
    tris = []
    for i in range(u_count):
        for j in range(v_count):
            a = i * v_count + j
            b = ((i + 1) % u_count) * v_count + j
            c = ((i + 1) % u_count) * v_count + (j + 1) % v_count
            d = i * v_count + (j + 1) % v_count
            tris += [(a, b, c), (a, c, d)]
    return verts, tris


def signed_volume(verts, tris):
    return sum(sum(x * y for x, y in zip(verts[a], cross(verts[b], verts[c]))) for a, b, c in tris) / 6.0


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--winding", choices=["outward", "inward", "mixed"], default="outward")
    p.add_argument("--u", type=int, default=400)
    p.add_argument("--v", type=int, default=24)
    args = p.parse_args()
    verts, tris = mesh(args.u, args.v)
    if signed_volume(verts, tris) < 0:
        tris = [(a, c, b) for a, b, c in tris]
    if args.winding != "outward":
        tris = [(a, c, b) if args.winding == "inward" or n % 3 == 0 else (a, b, c) for n, (a, b, c) in enumerate(tris)]
    with open(args.out, "w") as f:
        f.write(f"# (2, 3) torus knot tube, {len(tris)} triangles, wound {args.winding} (tools/make_knot_mesh.py)\n")
        for v in verts:
            f.write("v {:.6f} {:.6f} {:.6f}\n".format(*v))
        for a, b, c in tris:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")


if __name__ == "__main__":
    main()
