#!/usr/bin/env python3
"""Writes emissive_grid.obj for emissive_triangles.yaml: a 32 x 32 grid of small, separate
triangles just under the 3 x 3 m ceiling (y = 2.2) of the suite's box, 1,024 in all, each
with its own three vertices. Generated rather than committed, like every large input."""
import sys


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "emissive_grid.obj"
    n, size, y = 32, 2.4, 2.15  # grid cells, grid width (m), height under the ceiling
    cell = size / n
    side = 0.6 * cell  # each triangle fills part of its cell: separate emitters, gaps between
    lines = ["# emissive_grid.obj: 32 x 32 small triangles (make_emissive_grid.py)"]
    faces = []
    for i in range(n):
        for j in range(n):
            x0 = -size / 2 + (i + 0.2) * cell
            z0 = -size / 2 + (j + 0.2) * cell
            lines += [f"v {x0:.6f} {y} {z0:.6f}", f"v {x0 + side:.6f} {y} {z0:.6f}",
                      f"v {x0:.6f} {y} {z0 + side:.6f}"]
            k = 3 * (i * n + j) + 1
            faces.append(f"f {k} {k + 1} {k + 2}")
    with open(out, "w") as f:
        f.write("\n".join(lines + faces) + "\n")


main()
