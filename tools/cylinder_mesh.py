#!/usr/bin/python3
"""A Gmsh MSH 4.1 (ASCII) mesh of a thick cylinder's sector, for DIMENSION 3 scenes (`GMSH name FILE f`),
where no Gmsh is at hand: radii a < b, the angle from 0 to THETA degrees about z, the height from 0
to H, nr x nt x nz cells, HEX20 (default: the mid-edge nodes on the arcs, quadratic geometry) or HEX8.

    tools/cylinder_mesh.py OUT.msh a b THETA H nr nt nz [HEX8|HEX20]

Physical groups: the volume "body" (an element group `name.body`), the surfaces (node groups, with
their faces for PRESSURE) "inner" (r = a), "outer" (r = b), "theta0" (the plane y = 0), "theta1"
(the plane at THETA), "bottom" (z = 0), "top" (z = H). Node order and cells as Gmsh writes them
(8- and 20-node hexahedra, 4- and 8-node quadrangles); the cells' (r, theta, z) axes are right-handed.
"""
import math
import sys

HEX_CORNERS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
HEX20_EDGES = [(0, 1), (0, 3), (0, 4), (1, 2), (1, 5), (2, 3), (2, 6), (3, 7), (4, 5), (4, 7), (5, 6), (6, 7)]
SURFACES = ['inner', 'outer', 'theta0', 'theta1', 'bottom', 'top']


def cylinder(a, b, theta_deg, h, n, quadratic=True):
    """(nodes [(x, y, z)], hexahedra [node ids], faces {surface: [node ids]}), ids from 1."""
    st = 2 if quadratic else 1
    g = [st * n[0], st * n[1], st * n[2]]
    ids, nodes = {}, []
    theta = math.radians(theta_deg)
    for k in range(g[2] + 1):
        for j in range(g[1] + 1):
            for i in range(g[0] + 1):
                if quadratic and (i % 2) + (j % 2) + (k % 2) >= 2:
                    continue                     # no node at a face's or a cell's centre
                r = a + (b - a) * i / g[0]
                t = theta * j / g[1]
                ids[(i, j, k)] = len(nodes) + 1
                nodes.append((r * math.cos(t), r * math.sin(t), h * k / g[2]))

    def hexa(c):
        corners = [tuple(c[d] + st * o[d] for d in range(3)) for o in HEX_CORNERS]
        cell = [ids[p] for p in corners]
        if quadratic:
            cell += [ids[tuple((corners[p][d] + corners[q][d]) // 2 for d in range(3))] for p, q in HEX20_EDGES]
        return cell

    def quad(p0, du, dv):
        """The face from grid point p0 along the grid directions du, dv (unit vectors), counter-clockwise
        seen along du x dv: corners, then (quadratic) the mid-side nodes 1-2, 2-3, 3-4, 4-1."""
        c = [p0, tuple(p0[d] + st * du[d] for d in range(3)), tuple(p0[d] + st * (du[d] + dv[d]) for d in range(3)),
             tuple(p0[d] + st * dv[d] for d in range(3))]
        f = [ids[p] for p in c]
        if quadratic:
            f += [ids[tuple((c[m][d] + c[(m + 1) % 4][d]) // 2 for d in range(3))] for m in range(4)]
        return f

    hexas = [hexa((st * i, st * j, st * k)) for k in range(n[2]) for j in range(n[1]) for i in range(n[0])]
    ex, ey, ez = (1, 0, 0), (0, 1, 0), (0, 0, 1)
    faces = {
        'inner': [quad((0, st * j, st * k), ez, ey) for k in range(n[2]) for j in range(n[1])],
        'outer': [quad((g[0], st * j, st * k), ey, ez) for k in range(n[2]) for j in range(n[1])],
        'theta0': [quad((st * i, 0, st * k), ex, ez) for k in range(n[2]) for i in range(n[0])],
        'theta1': [quad((st * i, g[1], st * k), ez, ex) for k in range(n[2]) for i in range(n[0])],
        'bottom': [quad((st * i, st * j, 0), ey, ex) for j in range(n[1]) for i in range(n[0])],
        'top': [quad((st * i, st * j, g[2]), ex, ey) for j in range(n[1]) for i in range(n[0])],
    }
    return nodes, hexas, faces


def write_msh(path, nodes, hexas, faces, quadratic=True):
    """MSH 4.1 ASCII: one surface entity per physical surface, one volume entity "body"."""
    lo = [min(p[d] for p in nodes) for d in range(3)]
    hi = [max(p[d] for p in nodes) for d in range(3)]
    box = ' '.join('%.17g' % x for x in lo + hi)
    with open(path, 'w') as f:
        f.write('$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n%d\n' % (len(SURFACES) + 1))
        for s, name in enumerate(SURFACES):
            f.write('2 %d "%s"\n' % (s + 1, name))
        f.write('3 %d "body"\n$EndPhysicalNames\n' % (len(SURFACES) + 1))
        f.write('$Entities\n0 0 %d 1\n' % len(SURFACES))
        for s in range(len(SURFACES)):
            f.write('%d %s 1 %d 0\n' % (s + 1, box, s + 1))
        f.write('1 %s 1 %d 0\n$EndEntities\n' % (box, len(SURFACES) + 1))
        f.write('$Nodes\n1 %d 1 %d\n3 1 0 %d\n' % (len(nodes), len(nodes), len(nodes)))
        f.write(''.join('%d\n' % (i + 1) for i in range(len(nodes))))
        f.write(''.join('%.17g %.17g %.17g\n' % p for p in nodes))
        nface = sum(len(v) for v in faces.values())
        total = nface + len(hexas)
        f.write('$EndNodes\n$Elements\n%d %d 1 %d\n' % (len(SURFACES) + 1, total, total))
        tag = 0
        for s, name in enumerate(SURFACES):
            f.write('2 %d %d %d\n' % (s + 1, 16 if quadratic else 3, len(faces[name])))
            for q in faces[name]:
                tag += 1
                f.write('%d %s\n' % (tag, ' '.join(map(str, q))))
        f.write('3 1 %d %d\n' % (17 if quadratic else 5, len(hexas)))
        for c in hexas:
            tag += 1
            f.write('%d %s\n' % (tag, ' '.join(map(str, c))))
        f.write('$EndElements\n')


def main(argv):
    if len(argv) not in (9, 10):
        sys.stderr.write(__doc__)
        return 2
    out = argv[1]
    a, b, theta, h = (float(x) for x in argv[2:6])
    n = [int(x) for x in argv[6:9]]
    kind = argv[9].upper() if len(argv) == 10 else 'HEX20'
    if not (0 < a < b and 0 < theta <= 360 and h > 0 and min(n) >= 1 and kind in ('HEX8', 'HEX20')):
        sys.stderr.write('cylinder_mesh: expected 0 < a < b, 0 < THETA <= 360, H > 0, counts >= 1, HEX8 or HEX20\n')
        return 2
    quadratic = kind == 'HEX20'
    nodes, hexas, faces = cylinder(a, b, theta, h, n, quadratic)
    write_msh(out, nodes, hexas, faces, quadratic)
    print('%s: %d nodes, %d %s cells' % (out, len(nodes), len(hexas), kind))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
