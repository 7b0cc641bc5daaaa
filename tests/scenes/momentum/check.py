"""Momentum through collisions (issue 11): two free bodies colliding node to node (GAP) keep
total linear and angular momentum (history.csv momentum_x, momentum_y, angular_momentum: t_k'M v
with the rigid modes, the rotation about the origin in the reference configuration) in every
impact mode, including a spinning body hitting another.

two_beams.dat: beam a translates at 1 m/s and spins at 2 rad/s, beam b at rest. The contact
impulses act along the line of the nodes and the impact corrections along c_j, so both momenta
are kept by the multipliers, (12)-(16), and PERSIST, which scales a group about its rigid motion
(translations and rotation; scaling about the centre-of-mass translation alone changed the
angular momentum by 4.6 %). Asserted: drift <= 1e-12 x the momentum scale (m v for linear,
the initial angular momentum for angular), a collision happened, balance (PAPER, PERSIST).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
for mode in ['PAPER', 'PERSIST', 'OFF', 'MASSLESS', 'SYMMETRIC']:
    out = sc.run_ok(os.path.join(HERE, 'two_beams.dat'), ['SCHEME.IMPACT=' + mode])
    h = sc.history(out)
    ev = cc.events(out)
    p = np.hypot(h['momentum_x'][0], h['momentum_y'][0])
    sc.report('two beams %s: the beams collide' % mode, len(ev) > 0 and np.any(h['active_contacts'] > 0))
    for col, scale in [('momentum_x', p), ('momentum_y', p), ('angular_momentum', abs(h['angular_momentum'][0]))]:
        drift = np.abs(h[col] - h[col][0]).max()
        sc.report('two beams %s: %s kept (1e-12)' % (mode, col), drift <= 1e-12 * scale,
                  'drift %.3e, scale %.3e' % (drift, scale))
    if mode != 'OFF':
        cc.check_balance('two beams ' + mode, out)
