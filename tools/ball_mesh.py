#!/usr/bin/python3
"""A solid ball of TET10 for 3D contact studies (a sphere spinning on a rough floor: issue 33),
written directly in Gmsh's MSH 2.2 ASCII format (no Gmsh on this machine).

The cube [-1, 1]³ cut into (2n)³ cells, each into Kuhn's six tetrahedra (the diagonal from the cell's
low corner to its high one, as BOX … TYPE TET10: conforming), then the corners mapped onto the ball
by the smooth cube-to-ball map p = R (x √(1 - y²/2 - z²/2 + y²z²/3), and cyclically) (the cube's
faces land on the sphere); the mid-edge nodes
halfway between their corners, those of the surface's edges pushed out radially onto the sphere
(straight sides inside, curved ones on the sphere). Centre (0, 0,
R): the ball touches z = 0 at its south pole, a node. Physical groups: "ball" (the TET10), "surface"
(the TRI6 of the boundary).

usage: ball_mesh.py N R OUT.msh     (N >= 1: 2N cells across a diameter)
"""
import sys

import numpy as np

# Kuhn's six tetrahedra of a cell: the axes in the order of each permutation; the odd ones with
# their last two vertices swapped (a positive volume). TET10 mid-edges in Gmsh's order.
PERM = [(0, 1, 2), (1, 2, 0), (2, 0, 1), (0, 2, 1), (2, 1, 0), (1, 0, 2)]
TEDGE = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]
FACES = [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)]


def main():
    n, radius, out = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
    m = 4 * n                                    # half-cell grid points per axis minus one
    index = {}
    coords = []

    centre = np.array([0.0, 0.0, radius])

    def mapped(q):
        x, y, z = np.array(q, dtype=float) / (2 * n) - 1.0       # in [-1, 1]^3
        return centre + radius * np.array([x * np.sqrt(1 - y * y / 2 - z * z / 2 + y * y * z * z / 3),
                                           y * np.sqrt(1 - z * z / 2 - x * x / 2 + z * z * x * x / 3),
                                           z * np.sqrt(1 - x * x / 2 - y * y / 2 + x * x * y * y / 3)])

    def node(q, ends=None):
        q = tuple(q)
        if q not in index:
            if ends is None:
                coords.append(mapped(q))
            else:                                # a mid-edge node: halfway, or on the sphere
                a, b = ends
                p = 0.5 * (mapped(a) + mapped(b))
                if all(max(abs(c - m / 2) for c in e) == m / 2 for e in (a, b)) and \
                        any(a[ax] == b[ax] and a[ax] in (0, m) for ax in range(3)):
                    p = centre + radius * (p - centre) / np.linalg.norm(p - centre)
                coords.append(p)
            index[q] = len(coords)
        return index[q]

    tets, tris = [], []
    for k in range(2 * n):
        for j in range(2 * n):
            for i in range(2 * n):
                c = np.array([2 * i, 2 * j, 2 * k])
                for p, perm in enumerate(PERM):
                    v = np.zeros(3, dtype=int)
                    t = [c.copy()]
                    v[perm[0]] = 2
                    t.append(c + v)
                    v[perm[1]] = 2
                    t.append(c + v)
                    t.append(c + 2)
                    if p > 2:
                        t[2], t[3] = t[3], t[2]
                    tets.append([node(q) for q in t] + [node((t[a] + t[b]) // 2, (t[a], t[b])) for a, b in TEDGE])
                    # boundary faces: three vertices on one face of the cube, outward by the centroid
                    for f in FACES:
                        tv = [t[a] for a in f]
                        for ax in range(3):
                            for side in (0, m):
                                if all(q[ax] == side for q in tv):
                                    tri = list(f)
                                    a, b, d = [coords[node(t[x]) - 1] for x in tri]
                                    nrm = np.cross(b - a, d - a)
                                    if np.dot(nrm, a - np.array([0.0, 0.0, radius])) < 0.0:
                                        tri = [tri[0], tri[2], tri[1]]
                                    ends = [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])]
                                    tris.append([node(t[x]) for x in tri] + [node((t[a] + t[b]) // 2, (t[a], t[b]))
                                                                             for a, b in ends])
    with open(out, 'w') as f:
        f.write('$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 1 "surface"\n3 2 "ball"\n'
                '$EndPhysicalNames\n$Nodes\n%d\n' % len(coords))
        for k, x in enumerate(coords):
            f.write('%d %.17g %.17g %.17g\n' % (k + 1, x[0], x[1], x[2]))
        f.write('$EndNodes\n$Elements\n%d\n' % (len(tris) + len(tets)))
        e = 0
        for tri in tris:
            e += 1
            f.write('%d 9 2 1 1 %s\n' % (e, ' '.join(str(v) for v in tri)))
        for tet in tets:
            e += 1
            f.write('%d 11 2 2 2 %s\n' % (e, ' '.join(str(v) for v in tet)))
        f.write('$EndElements\n')
    print('%s: %d nodes, %d TET10, %d TRI6 on the sphere' % (out, len(coords), len(tets), len(tris)))


if __name__ == '__main__':
    main()
