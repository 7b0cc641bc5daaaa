#!/usr/bin/python3
"""A structured ring mesh as inputs/ring.geo makes it (outer radius 0.1 m, inner 0.08 m), written
directly in Gmsh's MSH 2.2 ASCII format, for refinement studies without Gmsh: 4 x n QUAD4 around
(n per quarter), m through the wall, physical groups "outer" (the LINE2 elements of the outer
circle) and "ring" (the quads, counter-clockwise). inputs/ring.msh is n = 12, m = 3.

usage: ring_mesh.py N M OUT.msh
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import msh22  # noqa: E402


def main():
    n, m, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    r_in, r_out = 0.08, 0.1
    nt = 4 * n                        # nodes around
    nodes = []                        # (x, y), index = j * nt + i (j through the wall, 0 = inner)
    for j in range(m + 1):
        r = r_in + (r_out - r_in) * j / m
        for i in range(nt):
            a = 2.0 * math.pi * i / nt
            nodes.append((r * math.cos(a), r * math.sin(a)))
    quads, lines = [], []
    for j in range(m):
        for i in range(nt):
            i2 = (i + 1) % nt
            # (inner i, inner i+1, outer i+1, outer i): counter-clockwise in the x-y plane
            quads.append((j * nt + i + 1, j * nt + i2 + 1, (j + 1) * nt + i2 + 1, (j + 1) * nt + i + 1))
    for i in range(nt):
        lines.append((m * nt + i + 1, m * nt + (i + 1) % nt + 1))
    msh22.write(out, [(1, 1, 'outer'), (2, 2, 'ring')], nodes,
                [(1, 1, list(ln)) for ln in lines] + [(3, 2, list(q)) for q in quads])


if __name__ == '__main__':
    main()
