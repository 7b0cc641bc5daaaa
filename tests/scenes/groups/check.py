"""GROUP by geometry and by operation (issue 35, item 4; docs/input.md, "Groups").

On a 10 x 4 QUAD4 rectangle of 1 x 0.4 m (nodes every 0.1 m), the groups written to fields.h5
(/groups) are exactly the nodes and elements the geometry gives:
- NODES BOX 0.2 0 0.5 0.2: 4 x 3 = 12 nodes (the bounds inclusive); ELEMENTS BOX: the 3 x 2 = 6
  elements whose every node is inside;
- NODES SPHERE 0.5 0.2 RADIUS 0.1: the centre and its 4 neighbours;
- NODES PLANE 0.3 0 NORMAL 1 0 TOLERANCE 0: the 5 nodes of the line x = 0.3; OF r.bottom: 1;
- INTERSECTION of the box and the line: 3 nodes; DIFFERENCE: 9;
- a union of groups (NODES g1 g2) as before; a group built by geometry serves a FIX like any other.
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

SCENE = sc.write_scene('groups.dat', """
RECTANGLE r ORIGIN 0 0 SIZE 1 0.4 ELEMENTS 10 4 TYPE QUAD4
GROUP     inbox NODES BOX 0.2 0 0.5 0.2
GROUP     ebox ELEMENTS BOX 0.2 0 0.5 0.2
GROUP     disk NODES SPHERE 0.5 0.2 RADIUS 0.1
GROUP     xline NODES PLANE 0.3 0 NORMAL 1 0 TOLERANCE 0
GROUP     foot NODES PLANE 0.3 0 NORMAL 2 0 TOLERANCE 0 OF r.bottom
GROUP     both NODES INTERSECTION inbox xline
GROUP     rest NODES DIFFERENCE inbox xline
GROUP     ends NODES r.left r.right
GROUP     slant NODES PLANE 0 0 NORMAL -0.4 1 TOLERANCE 1e-9
MATERIAL  st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
SECTION   s THICKNESS 0.01
MODEL     r MATERIAL st SECTION s
FIX       ends UX UY
INITIAL   r VELOCITY 0 1
TIME      STEP 1e-5 END 1e-4
OUTPUT    FIELDS EVERY 10
""")
out = sc.run_ok(SCENE)
with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
    x = np.array(f['mesh/coordinates'])[:, :2]
    ng = {k: np.array(f['groups/nodes'][k]) for k in f['groups/nodes']}
    eg = {k: np.array(f['groups/elements'][k]) for k in f['groups/elements']}


def pts(name):
    return sorted((round(a, 9), round(b, 9)) for a, b in x[ng[name]])


grid = [(round(0.1 * i, 9), round(0.1 * j, 9)) for i in range(11) for j in range(5)]
sc.report('NODES BOX: the 12 nodes of [0.2, 0.5] x [0, 0.2], bounds inclusive',
          pts('inbox') == sorted(p for p in grid if 0.2 - 1e-9 <= p[0] <= 0.5 + 1e-9 and p[1] <= 0.2 + 1e-9), str(pts('inbox')))
sc.report('ELEMENTS BOX: the 6 elements inside', len(eg.get('ebox', [])) == 6, str(eg.get('ebox')))
sc.report('NODES SPHERE: the centre and its 4 neighbours', pts('disk') == sorted([(0.5, 0.2), (0.4, 0.2), (0.6, 0.2),
                                                                                   (0.5, 0.1), (0.5, 0.3)]), str(pts('disk')))
sc.report('NODES PLANE: the 5 nodes of x = 0.3', pts('xline') == [(0.3, round(0.1 * j, 9)) for j in range(5)], str(pts('xline')))
sc.report('NODES PLANE ... OF r.bottom: 1 node (the normal need not be a unit vector)', pts('foot') == [(0.3, 0.0)],
          str(pts('foot')))
sc.report('INTERSECTION: 3 nodes; DIFFERENCE: 9', len(ng['both']) == 3 and len(ng['rest']) == 9 and
          not set(ng['both']) & set(ng['rest']) and set(ng['both']) | set(ng['rest']) == set(ng['inbox']))
sc.report('a union of groups (the two ends: 10 nodes)', len(ng['ends']) == 10)
sc.report('an oblique PLANE (y = 0.4 x, tolerance 1e-9): the nodes on it, (0, 0), (0.5, 0.2), (1, 0.4)',
          pts('slant') == [(0.0, 0.0), (0.5, 0.2), (1.0, 0.4)], str(pts('slant')))
