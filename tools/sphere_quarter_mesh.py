#!/usr/bin/python3
"""A quarter of a solid ball in TET10, graded towards its south pole, for 3D contact studies (Hertz:
inputs/hertz_3d.dat), written directly in Gmsh's MSH 2.2 ASCII format (no Gmsh on this machine).

The ball: radius R, centre (0, 0, R), so that its south pole touches z = 0 at the origin; the quarter
x >= 0, y >= 0 (the planes x = 0 and y = 0 are symmetry planes). The points: shells about the pole
of radius d_0 = 0, d_(k+1) = d_k + h(d_k) cos(t/2) (t the polar angle of the shell's rim on the sphere:
the rims h apart along it), h(d) = min(HMAX, H0 + G d); on each shell its cap inside
the ball (angle a from the axis, cos a >= d / 2R: the cap's rim lies on the sphere), rings of
spacing h(d) in a and in the quarter of azimuth [0, pi/2] (the rings' ends on the symmetry planes).
The points strictly inside are moved by a small pseudo-random offset (5 % of h, fixed seed) so that
no four are cospherical; then Delaunay (scipy's Qhull). Tetrahedra of no volume on the hull (four
points of a symmetry plane) and slivers of four points of the sphere are dropped. TET10 with straight
sides: the mid-edge nodes halfway (a surface edge's sagitta h²/8R is 2e-8 m at the pole's 4e-5 m
against Hertz's approach of 1.8e-5 m; curving them inverted the slivers next to the sphere). Physical groups: "ball" (the TET10), "surface" (the TRI6 of the sphere:
the free faces not on a symmetry plane), "xsym" and "ysym" (points: every node on x = 0, y = 0).

usage: sphere_quarter_mesh.py R H0 G HMAX OUT.msh    (inputs/hertz_3d.msh: 0.01 6e-5 0.3 2e-3)
"""
import math
import sys

import numpy as np
from scipy.spatial import Delaunay

TEDGE = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]      # Gmsh's TET10 mid-edge order
FACES = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]           # outward for a positive tetrahedron


def main():
    r, h0, g, hmax, out = float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
    h = lambda d: min(hmax, h0 + g * d)
    c = np.array([0.0, 0.0, r])
    rng = np.random.default_rng(12345)
    pts, inner = [np.zeros(3)], [False]
    d = h0
    while d < 2.0 * r - 0.5 * h(2.0 * r):
        hd = h(d)
        amax = math.acos(min(1.0, d / (2.0 * r)))
        na = max(1, int(math.ceil(amax * d / hd)))
        for j in range(na + 1):
            a = amax * j / na
            rim = j == na
            ring = d * math.sin(a)
            nphi = max(1, int(math.ceil(0.5 * math.pi * ring / hd))) if j > 0 else 0
            for k in range(nphi + 1):
                phi = 0.5 * math.pi * k / nphi if nphi else 0.0
                p = np.array([ring * math.cos(phi), ring * math.sin(phi), d * math.cos(a)])
                if rim:
                    p = c + r * (p - c) / np.linalg.norm(p - c)       # on the sphere to round-off
                if k == 0:
                    p[1] = 0.0
                if k == nphi and nphi:
                    p[0] = 0.0
                if j == 0:
                    p[0] = p[1] = 0.0
                interior = not rim and 0 < k < nphi and j > 0
                if interior:
                    p = p + 0.05 * hd * rng.uniform(-1.0, 1.0, 3)
                pts.append(p)
                inner.append(interior)
        # the next shell: its rim (on the sphere, at the polar angle t about the centre, d = 2R sin(t/2))
        # one h further along the sphere, R dt = dd / cos(t/2)
        d += max(0.2, math.sqrt(max(0.0, 1.0 - (d / (2.0 * r)) ** 2))) * hd
    pts.append(np.array([0.0, 0.0, 2.0 * r]))
    inner.append(False)
    pts = np.array(pts)
    on_sphere = np.abs(np.linalg.norm(pts - c, axis=1) - r) <= 1e-9 * r
    on_x = pts[:, 0] == 0.0
    on_y = pts[:, 1] == 0.0
    tets = []
    for t in Delaunay(pts).simplices:
        a, b, cc, dd = pts[t]
        vol = np.dot(np.cross(b - a, cc - a), dd - a) / 6.0
        hl = max(np.linalg.norm(b - a), np.linalg.norm(cc - a), np.linalg.norm(dd - a))
        if abs(vol) <= 1e-10 * hl ** 3:
            if on_x[t].all() or on_y[t].all() or on_sphere[t].all():
                continue
            sys.exit('sphere_quarter_mesh: a flat tetrahedron inside the ball (%s)' % t)
        if on_sphere[t].all() and abs(vol) <= 1e-2 * hl ** 3:
            continue                     # a sliver of four points of the sphere, on the hull: dropped
        tets.append(list(t) if vol > 0 else [t[0], t[2], t[1], t[3]])
    count = {}                           # the faces' tetrahedra: one on the boundary
    for t in tets:
        for f in FACES:
            key = tuple(sorted(t[i] for i in f))
            count[key] = count.get(key, 0) + 1
    nodes = [tuple(p) for p in pts]
    mid = {}

    def midpoint(i, j):
        key = (min(i, j), max(i, j))
        if key not in mid:
            p = 0.5 * (pts[i] + pts[j])
            if on_x[i] and on_x[j]:
                p[0] = 0.0
            if on_y[i] and on_y[j]:
                p[1] = 0.0
            nodes.append(tuple(p))
            mid[key] = len(nodes) - 1
        return mid[key]

    tet10 = [t + [midpoint(t[a], t[b]) for a, b in TEDGE] for t in tets]
    surface = []
    for t in tets:
        for f in FACES:
            v = [t[i] for i in f]
            if count[tuple(sorted(v))] != 1 or on_x[v].all() or on_y[v].all():
                continue
            # the sphere's faces (and, along its rims on the symmetry planes, the hull's faces that join
            # the rim to the planes' points: the sphere's facets there)
            if np.max(r - np.linalg.norm(pts[v] - c, axis=1)) > hmax:
                sys.exit('sphere_quarter_mesh: a free face on no boundary (%s): the hull is not the quarter ball' % v)
            surface.append(v + [mid[(min(v[0], v[1]), max(v[0], v[1]))], mid[(min(v[1], v[2]), max(v[1], v[2]))],
                                mid[(min(v[2], v[0]), max(v[2], v[0]))]])
    xyz = np.array(nodes)
    groups = {'xsym': np.nonzero(xyz[:, 0] == 0.0)[0], 'ysym': np.nonzero(xyz[:, 1] == 0.0)[0]}
    with open(out, 'w') as f:
        f.write('$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n2 1 "surface"\n0 2 "xsym"\n0 3 "ysym"\n'
                '3 4 "ball"\n$EndPhysicalNames\n$Nodes\n%d\n' % len(nodes))
        for k, (x, y, z) in enumerate(nodes):
            f.write('%d %.17g %.17g %.17g\n' % (k + 1, x, y, z))
        nel = len(surface) + sum(len(v) for v in groups.values()) + len(tet10)
        f.write('$EndNodes\n$Elements\n%d\n' % nel)
        e = 0
        for t6 in surface:
            e += 1
            f.write('%d 9 2 1 1 %s\n' % (e, ' '.join(str(i + 1) for i in t6)))
        for tag, name in ((2, 'xsym'), (3, 'ysym')):
            for n in groups[name]:
                e += 1
                f.write('%d 15 2 %d %d %d\n' % (e, tag, tag, n + 1))
        for t10 in tet10:
            e += 1
            f.write('%d 11 2 4 4 %s\n' % (e, ' '.join(str(i + 1) for i in t10)))
        f.write('$EndElements\n')
    q = min(abs(np.dot(np.cross(pts[t[1]] - pts[t[0]], pts[t[2]] - pts[t[0]]), pts[t[3]] - pts[t[0]])) /
            max(np.linalg.norm(pts[t[i]] - pts[t[j]]) for i in range(4) for j in range(i)) ** 3 for t in tets)
    print('%s: %d nodes, %d TET10 (%d vertices), %d TRI6 on the sphere; worst volume / edge^3 %.2e'
          % (out, len(nodes), len(tet10), len(pts), len(surface), q))


if __name__ == '__main__':
    main()
