"""Nonlinear material and unilateral contact together (issue 4: "must work together with the
nonlinear-material iteration").

A nonlinear-elastic bar dropped on the ground: the steps in contact iterate eq (9) with the
multipliers inside the loop. With the energy correction (ON, the default) and the impact
correction (PAPER or PERSIST), kinetic + internal - external must stay constant to the
solver tolerance: |balance| <= 1e-10 x max(kinetic + internal). The bar must really bounce
(a contact is established and released, the steps in contact iterate more than once), and it
must never penetrate the ground by more than the contact tolerance. The same run in
PRECISION EXTENDED agrees.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

SCENE = 'tests/scenes/contact_nonlinear/bar_drop.dat'
for mode in ('PAPER', 'PERSIST'):
    for prec in ('DOUBLE', 'EXTENDED'):
        tag = '%s %s' % (mode, prec)
        out = sc.run_ok(SCENE, ['SCHEME.IMPACT=' + mode, 'SCHEME.PRECISION=' + prec])
        hist = sc.history(out)
        probes = sc.read_csv(os.path.join(out, 'probes.csv'))
        rel, _ = sc.relative_balance(out)
        print('# %s: max |balance| / max(kinetic + internal) = %.3e' % (tag, rel))
        sc.report(tag + ': |balance| <= 1e-10 x total energy', rel <= 1e-10, 'measured %.3e' % rel)
        events = open(os.path.join(out, 'events.csv')).read().splitlines()[1:]
        kinds = [e.split(',')[4] for e in events]
        sc.report(tag + ': the bar lands and leaves', 'establish' in kinds and 'release' in kinds,
                  'events: %s' % kinds[:6])
        iters = hist['iterations'][hist['active_contacts'] > 0]
        sc.report(tag + ': steps in contact iterate (nonlinear law)', iters.size > 0 and iters.max() >= 2,
                  'iterations in contact: %s' % (np.unique(iters),))
        lowest = probes['bar.start.UY'].min() + 0.01
        sc.report(tag + ': no penetration beyond 1e-12 x bar length', lowest >= -1e-12 * 0.5,
                  'lowest gap %.3e m' % lowest)
        sc.report(tag + ': energy restored at impacts', hist['correction'][-1] > 0.0,
                  'correction %.3e' % hist['correction'][-1])
