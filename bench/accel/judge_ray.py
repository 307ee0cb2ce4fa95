#!/usr/bin/env python3
"""Judges one ray against a mesh in exact arithmetic.

Two float ray-triangle tests can disagree on a ray that passes within rounding of an edge;
`embree_compare --dump-mismatches N` prints such rays. This script decides each one exactly:
vertices and ray are taken as the float32 values the tracers see, and every candidate
triangle's barycentrics and distance are computed with rational numbers. It prints the
triangles the ray really hits (t > t_min) and the nearest near misses with their exact
barycentrics, so it shows which tracer was right and by how much.

    bench/accel/judge_ray.py MESH OX OY OZ DX DY DZ [T_MIN]

MESH: an OFF file (libcgal-demo's) or a binary little-endian PLY with float x, y, z first
(what `tessera-bench mesh` writes). Standard library only.
"""
import struct
import sys
from fractions import Fraction


def f32(x):
    return struct.unpack("<f", struct.pack("<f", float(x)))[0]


def load_off(path):
    tokens = []
    for line in open(path):
        tokens += line.split("#")[0].split()
    if tokens[0] != "OFF":
        raise SystemExit(f"{path}: not an OFF file")
    nv, nf = int(tokens[1]), int(tokens[2])
    i = 4
    vertices = [tuple(f32(x) for x in tokens[i + 3 * k:i + 3 * k + 3]) for k in range(nv)]
    i += 3 * nv
    faces = []
    for _ in range(nf):
        n = int(tokens[i])
        faces.append([int(x) for x in tokens[i + 1:i + 1 + n]])
        i += 1 + n
    return vertices, faces


def load_ply(path):
    data = open(path, "rb")
    header = []
    while True:
        line = data.readline().decode().strip()
        header.append(line)
        if line == "end_header":
            break
    if "format binary_little_endian 1.0" not in header:
        raise SystemExit(f"{path}: only binary little-endian PLY is read")
    counts = {h.split()[1]: int(h.split()[2]) for h in header if h.startswith("element")}
    vertex_props, face_list, section = 0, None, None
    for h in header:
        if h.startswith("element"):
            section = h.split()[1]
        elif h.startswith("property list") and section == "face":
            face_list = h.split()[2:4]  # count type, index type
        elif h.startswith("property float") and section == "vertex":
            vertex_props += 1
    size = {"uchar": ("B", 1), "int": ("i", 4), "uint": ("I", 4)}
    vertices = [struct.unpack(f"<{vertex_props}f", data.read(4 * vertex_props))[:3]
                for _ in range(counts["vertex"])]
    count_fmt, count_size = size[face_list[0]]
    index_fmt, index_size = size[face_list[1]]
    faces = []
    for _ in range(counts["face"]):
        n = struct.unpack("<" + count_fmt, data.read(count_size))[0]
        faces.append(list(struct.unpack(f"<{n}{index_fmt}", data.read(n * index_size))))
    return vertices, faces


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def barycentrics(origin, direction, a, b, c):
    """(u, v, t) of the line's crossing of the triangle's plane, or None when parallel."""
    e1, e2 = sub(b, a), sub(c, a)
    p = cross(direction, e2)
    det = dot(e1, p)
    if det == 0:
        return None
    s = sub(origin, a)
    q = cross(s, e1)
    return dot(s, p) / det, dot(direction, q) / det, dot(e2, q) / det


def main():
    if len(sys.argv) not in (8, 9):
        raise SystemExit(__doc__)
    path = sys.argv[1]
    vertices, faces = load_off(path) if path.endswith(".off") else load_ply(path)
    triangles = [(f[0], f[j], f[j + 1]) for f in faces for j in range(1, len(f) - 1)]
    origin_f = [f32(x) for x in sys.argv[2:5]]
    direction_f = [f32(x) for x in sys.argv[5:8]]
    t_min = Fraction(f32(sys.argv[8])) if len(sys.argv) == 9 else Fraction(0)
    origin = tuple(Fraction(x) for x in origin_f)
    direction = tuple(Fraction(x) for x in direction_f)
    hits, near = [], []
    for k, (i, j, l) in enumerate(triangles):
        # Float prefilter with a wide margin; the decision below is exact.
        crossing = barycentrics(origin_f, direction_f, vertices[i], vertices[j], vertices[l])
        if crossing is None:
            continue
        u, v, t = crossing
        if u < -1e-3 or v < -1e-3 or u + v > 1 + 1e-3 or t <= float(t_min) - 1e-3:
            continue
        a, b, c = (tuple(Fraction(x) for x in vertices[m]) for m in (i, j, l))
        exact = barycentrics(origin, direction, a, b, c)
        if exact is None:
            continue
        u, v, t = exact
        w = 1 - u - v
        row = (float(t), k, float(u), float(v), float(w))
        if u >= 0 and v >= 0 and w >= 0 and t > t_min:
            hits.append(row)
        elif t > t_min:
            near.append((min(u, v, w), row))
    print(f"{len(triangles)} triangles")
    for t, k, u, v, w in sorted(hits):
        print(f"hit: triangle {k} at t = {t:.9g}, barycentrics {u:.3g} {v:.3g} {w:.3g}")
    if not hits:
        print("no triangle is hit")
    for _, (t, k, u, v, w) in sorted(near, key=lambda n: -n[0])[:2]:
        print(f"near miss: triangle {k} at t = {t:.9g}, barycentrics {u:.3g} {v:.3g} {w:.3g}")


if __name__ == "__main__":
    main()
