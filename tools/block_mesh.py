#!/usr/bin/python3
"""A structured QUAD8 mesh of the block x in [0, W], y in [-H, 0] (an axisymmetric half-space: x = r,
y the axis), graded geometrically toward the origin in both directions (the first element's size
h0, then each one g times the last, the last ones stretched to end at W and H), written in Gmsh's
MSH 2.2 ASCII format. Physical groups: lines "top" (y = 0), "bottom" (y = -H), "axis" (x = 0),
"side" (x = W) (3-node lines), surface "block" (QUAD8, counter-clockwise). For contact studies
under a rigid sphere (tests/scenes/curved_obstacle, Hertz).

usage: block_mesh.py W H H0 G OUT.msh
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import msh22  # noqa: E402


def graded(length, h0, g):
    """Breakpoints 0 = s0 < s1 < ... = length, sizes h0, h0 g, h0 g², ... scaled to end at length."""
    pts, h, s = [0.0], h0, 0.0
    while s + h < length:
        s += h
        pts.append(s)
        h *= g
    if length - pts[-1] < 0.5 * h / g and len(pts) > 1:
        pts.pop()
    pts.append(length)
    return pts


def main():
    w, hgt, h0, g, out = float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
    xs = graded(w, h0, g)
    ys = [-v for v in graded(hgt, h0, g)]       # 0 down to -H
    ys.reverse()                                 # -H ... 0
    nx, ny = len(xs) - 1, len(ys) - 1
    tag, nodes = {}, []

    def node(i, j):                              # i, j on the doubled lattice (mid-side points odd)
        if (i, j) not in tag:
            x = xs[i // 2] if i % 2 == 0 else 0.5 * (xs[i // 2] + xs[i // 2 + 1])
            y = ys[j // 2] if j % 2 == 0 else 0.5 * (ys[j // 2] + ys[j // 2 + 1])
            nodes.append((x, y))
            tag[(i, j)] = len(nodes)
        return tag[(i, j)]

    quads = []
    for e in range(nx):
        for f in range(ny):
            i, j = 2 * e, 2 * f
            c = [node(i, j), node(i + 2, j), node(i + 2, j + 2), node(i, j + 2)]
            m = [node(i + 1, j), node(i + 2, j + 1), node(i + 1, j + 2), node(i, j + 1)]
            quads.append(c + m)
    lines = []
    for e in range(nx):
        i = 2 * e
        lines.append((1, node(i, 2 * ny), node(i + 2, 2 * ny), node(i + 1, 2 * ny)))   # top
        lines.append((2, node(i, 0), node(i + 2, 0), node(i + 1, 0)))                   # bottom
    for f in range(ny):
        j = 2 * f
        lines.append((3, node(0, j), node(0, j + 2), node(0, j + 1)))                   # axis
        lines.append((4, node(2 * nx, j), node(2 * nx, j + 2), node(2 * nx, j + 1)))    # side
    msh22.write(out, [(1, 1, 'top'), (1, 2, 'bottom'), (1, 3, 'axis'), (1, 4, 'side'), (2, 5, 'block')], nodes,
                [(8, p, [a, b, c]) for p, a, b, c in lines] + [(16, 5, q) for q in quads])


if __name__ == '__main__':
    main()
