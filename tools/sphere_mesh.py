#!/usr/bin/python3
"""The meridian half-disk of a sphere for axisymmetric contact studies (Hertz), written directly in
Gmsh's MSH 2.2 ASCII format (no Gmsh on this machine): radius R, centre (0, R), so that its south
pole touches y = 0 at the origin; x = r >= 0, y the axis. TRI6 (6-node triangles, counter-clockwise,
the mid-side nodes of the arc on the circle), graded from a size h0 at the pole by h = h0 + g d (d the
distance to the pole) up to hmax: points on the arc and on the axis at that spacing, inside on
circles about the pole, then Delaunay (scipy). Physical groups: "ball" (the triangles), "surface"
(the LINE3 of the arc), "axis" (the LINE3 on x = 0).

usage: sphere_mesh.py R H0 G HMAX OUT.msh     (inputs/hertz.msh: 0.01 4e-5 0.2 1e-3)
"""
import math
import sys

import numpy as np
from scipy.spatial import Delaunay


def spacing(p, h0, g, hmax):
    return min(hmax, h0 + g * math.hypot(p[0], p[1]))


def main():
    r, h0, g, hmax, out = float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
    c = np.array([0.0, r])
    pts = []
    # the arc, from the south pole (angle -pi/2) to the north pole (pi/2)
    t = -0.5 * math.pi
    arc = []
    while t < 0.5 * math.pi:
        arc.append(t)
        p = c + r * np.array([math.cos(t), math.sin(t)])
        t += spacing(p, h0, g, hmax) / r
    if 0.5 * math.pi - arc[-1] < 0.5 * spacing(c + [0.0, r], h0, g, hmax) / r:
        arc.pop()
    arc.append(0.5 * math.pi)
    for t in arc:
        pts.append(c + r * np.array([math.cos(t), math.sin(t)]))
    pts[0] = np.array([0.0, 0.0])
    pts[-1] = np.array([0.0, 2.0 * r])
    # the axis, between the poles
    y = spacing((0.0, 0.0), h0, g, hmax)
    axis = []
    while y < 2.0 * r - 0.5 * spacing((0.0, 2 * r), h0, g, hmax):
        axis.append(y)
        y += spacing((0.0, y), h0, g, hmax)
    for y in axis:
        pts.append(np.array([0.0, y]))
    nb = len(pts)
    # inside: circles about the pole
    rho = spacing((0.0, 0.0), h0, g, hmax)
    while rho < 2.0 * r:
        hr = spacing((0.0, rho), h0, g, hmax)
        # the circle's points inside the half-disk: angles from the axis (0) towards x > 0
        n = max(1, int(math.ceil(math.pi * rho / hr)))
        for k in range(1, n):
            a = math.pi * k / n - 0.5 * math.pi          # from -pi/2 (down the axis) to pi/2 (up)
            p = np.array([rho * math.cos(a), rho * math.sin(a)])
            if p[0] < 0.5 * hr or np.linalg.norm(p - c) > r - 0.5 * hr:
                continue
            pts.append(p)
        rho += hr
    pts = np.array(pts)
    tri = Delaunay(pts).simplices
    keep = []
    for t3 in tri:
        a, b, d = pts[t3]
        area = 0.5 * ((b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]))
        if abs(area) < 1e-12 * r * r:
            continue
        keep.append(list(t3) if area > 0 else [t3[0], t3[2], t3[1]])
    # mid-side nodes (shared), the arc's on the circle
    nodes = [tuple(p) for p in pts]
    mid = {}

    def midpoint(i, j):
        key = (min(i, j), max(i, j))
        if key not in mid:
            p = 0.5 * (pts[i] + pts[j])
            on_arc = i < len(arc) and j < len(arc) and abs(i - j) == 1
            if on_arc:
                p = c + r * (p - c) / np.linalg.norm(p - c)
            if i < nb and j < nb and pts[i][0] == 0.0 and pts[j][0] == 0.0:
                p = np.array([0.0, p[1]])
            nodes.append(tuple(p))
            mid[key] = len(nodes) - 1
        return mid[key]

    tri6 = []
    for a, b, d in keep:
        tri6.append([a, b, d, midpoint(a, b), midpoint(b, d), midpoint(d, a)])
    surface = [(i, i + 1, mid[(i, i + 1)]) for i in range(len(arc) - 1) if (i, i + 1) in mid]
    on_axis = sorted([i for i in range(nb) if pts[i][0] == 0.0], key=lambda i: pts[i][1])
    axis_lines = [(a, b, mid[(min(a, b), max(a, b))]) for a, b in zip(on_axis[:-1], on_axis[1:])
                  if (min(a, b), max(a, b)) in mid]
    with open(out, 'w') as f:
        f.write('$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n1 1 "surface"\n1 2 "axis"\n2 3 "ball"\n'
                '$EndPhysicalNames\n$Nodes\n%d\n' % len(nodes))
        for k, (x, y) in enumerate(nodes):
            f.write('%d %.17g %.17g 0\n' % (k + 1, x, y))
        f.write('$EndNodes\n$Elements\n%d\n' % (len(surface) + len(axis_lines) + len(tri6)))
        e = 0
        for a, b, m in surface:
            e += 1
            f.write('%d 8 2 1 1 %d %d %d\n' % (e, a + 1, b + 1, m + 1))
        for a, b, m in axis_lines:
            e += 1
            f.write('%d 8 2 2 2 %d %d %d\n' % (e, a + 1, b + 1, m + 1))
        for t6 in tri6:
            e += 1
            f.write('%d 9 2 3 3 %s\n' % (e, ' '.join(str(i + 1) for i in t6)))
        f.write('$EndElements\n')
    print('%s: %d nodes, %d TRI6, %d arc sides' % (out, len(nodes), len(tri6), len(surface)))


if __name__ == '__main__':
    main()
