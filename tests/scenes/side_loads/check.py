"""PRESSURE and TRACTION on the free element sides of a node group (src/assembly/loads.f90).

block.dat: a block turned 30 deg, clamped on its bottom side, a pressure ramped to 1 MPa on its
top side (length 1 m, thickness 0.1 m) and a traction (0, 2e5) Pa on its right side (0.5 m),
damped to rest (ALPHA). The support reaction (PROBE blk.bottom RX, RY) at rest balances the
loads exactly: (-5e4, 86602.54 - 1e4) N. Asserted to 1e-9 relative (measured 4e-13) in QUAD8
(7 x 3) and QUAD4 (5 x 2): the consistent nodal forces of a side add up to the exact total
whatever the mesh; also in TRI6 (7 x 3 cells, 42 triangles) and TRI3. Balance <= 1e-10 of the
external work, with the damping column.

patch.dat: the patch test at rest. A plane-stress plate on rollers, a traction (1e8, 0) Pa on its
right side, damped to rest: sigma_xx = 1e8 Pa, sigma_yy = sigma_xy = 0 in every element
(fields.h5 stress, the mean over each element's stress points) to 1e-7 of 1e8 (measured 2e-9),
in TRI3, TRI6, QUAD4 and QUAD8.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
P, T, L, LR, TY = 1e6, 0.1, 1.0, 0.5, 2e5
S, C = math.sin(math.pi / 6), math.cos(math.pi / 6)
RX, RY = -P * L * T * S, P * L * T * C - T * LR * TY

for tag, sets in [('QUAD8 7 x 3', []), ('QUAD4 5 x 2', ['RECTANGLE.TYPE=QUAD4', 'RECTANGLE.ELEMENTS=5 2']),
                  ('TRI6 7 x 3', ['RECTANGLE.TYPE=TRI6']), ('TRI3 5 x 2', ['RECTANGLE.TYPE=TRI3', 'RECTANGLE.ELEMENTS=5 2'])]:
    out = sc.run_ok(os.path.join(HERE, 'block.dat'), sets)
    p = sc.probes(out)
    h = sc.history(out)
    sc.close('block %s: RX at rest = -p L t sin 30' % tag, p['blk.bottom.RX'][-1], RX, 1e-9)
    sc.close('block %s: RY at rest = p L t cos 30 - t L ty' % tag, p['blk.bottom.RY'][-1], RY, 1e-9)
    bal = abs(h['balance']).max() / abs(h['external']).max()
    sc.report('block %s: |balance| <= 1e-10 x external work (damping booked)' % tag, bal <= 1e-10, '%.3e' % bal)
    sc.report('block %s: damping removed energy' % tag, h['damping'][-1] > 0)

import h5py  # noqa: E402
SIG = 1e8
for et in ['TRI3', 'TRI6', 'QUAD4', 'QUAD8']:
    out = sc.run_ok(os.path.join(HERE, 'patch.dat'), ['RECTANGLE.TYPE=' + et])
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        s = f['step_000600/stress'][...]
    err = max(abs(s[:, 0] - SIG).max(), abs(s[:, 1]).max(), abs(s[:, 3]).max()) / SIG
    sc.report('patch %s at rest: sigma_xx = 1e8, sigma_yy = sigma_xy = 0 in every element (1e-7)' % et, err <= 1e-7,
              'relative error %.3e' % err)
