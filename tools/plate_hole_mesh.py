#!/usr/bin/python3
"""A structured QUAD8 mesh of the quarter plate with a hole of tests/scenes/kirsch (W x W, 1 x 1 m by
default, hole of radius a = 0.1 m at the origin), written in Gmsh's MSH 2.2 ASCII format, for refinement
studies without Gmsh. Each node lies on a ray from the origin, between the hole (s = 0) and the
outer sides (s = 1: x = W below 45 degrees, y = W above), at s = (g^t - 1)/(g - 1) (geometric
grading g toward the hole, t uniform); the mid-side nodes at the half parameters, so that the
hole's mid-side nodes lie on the circle. Physical groups: lines "bottom" (y = 0), "right" (x = W),
"top" (y = W), "left" (x = 0), "hole" (3-node lines), surface "plate" (QUAD8, counter-clockwise).

usage: plate_hole_mesh.py NT NR OUT.msh [GRADING [W]]   (NT elements around the quarter (even), NR radially;
       the plate's half width W, default 1)
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import msh22  # noqa: E402


def main():
    nt, nr, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    g = float(sys.argv[4]) if len(sys.argv) > 4 else 8.0
    a, w = 0.1, float(sys.argv[5]) if len(sys.argv) > 5 else 1.0
    ni, nj = 2 * nt + 1, 2 * nr + 1           # second-order lattice (mid-side points included)

    def point(i, j):
        th = 0.5 * math.pi * i / (ni - 1)
        t = j / (nj - 1)
        s = (g ** t - 1.0) / (g - 1.0)
        c, sn = math.cos(th), math.sin(th)
        if i == ni - 1:
            c = 0.0
        hole = (a * c, a * sn)
        edge = (w, w * sn / c) if th <= 0.25 * math.pi + 1e-15 else (w * c / sn, w)
        return ((1 - s) * hole[0] + s * edge[0], (1 - s) * hole[1] + s * edge[1])

    tag = {}
    nodes = []
    for j in range(nj):
        for i in range(ni):
            if i % 2 == 1 and j % 2 == 1:
                continue                      # no centre node (QUAD8)
            nodes.append(point(i, j))
            tag[(i, j)] = len(nodes)
    quads = []
    for e in range(nt):
        for f in range(nr):
            i, j = 2 * e, 2 * f
            # corners (i, j) -> (i, j+2) -> (i+2, j+2) -> (i+2, j): outward then counter-clockwise
            c = [tag[(i, j)], tag[(i, j + 2)], tag[(i + 2, j + 2)], tag[(i + 2, j)]]
            m = [tag[(i, j + 1)], tag[(i + 1, j + 2)], tag[(i + 2, j + 1)], tag[(i + 1, j)]]
            quads.append(c + m)
    lines = []                                # (physical, a, b, mid)
    for f in range(nr):
        j = 2 * f
        lines.append((1, tag[(0, j)], tag[(0, j + 2)], tag[(0, j + 1)]))                  # bottom
        lines.append((4, tag[(ni - 1, j)], tag[(ni - 1, j + 2)], tag[(ni - 1, j + 1)]))   # left
    for e in range(nt):
        i = 2 * e
        th = 0.5 * math.pi * (i + 1) / (ni - 1)
        phys = 2 if th < 0.25 * math.pi else 3                                           # right, top
        lines.append((phys, tag[(i, nj - 1)], tag[(i + 2, nj - 1)], tag[(i + 1, nj - 1)]))
        lines.append((5, tag[(i, 0)], tag[(i + 2, 0)], tag[(i + 1, 0)]))                 # hole
    msh22.write(out, [(1, 1, 'bottom'), (1, 2, 'right'), (1, 3, 'top'), (1, 4, 'left'), (1, 5, 'hole'), (2, 6, 'plate')],
                nodes, [(8, p, [n1, n2, n3]) for p, n1, n2, n3 in lines] + [(16, 6, q) for q in quads])


if __name__ == '__main__':
    main()
