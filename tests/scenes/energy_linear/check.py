"""Energy conservation of the trapezoidal rule on linear elastic scenes.

For linear elasticity the scheme conserves kinetic + strain energy exactly (method.md eq (8):
the lunule is zero), for any step: the balance column must stay at round-off,
max |balance| <= 1e-12 x max(kinetic + internal), over 10 000 steps of h = T1/1000 (accurate)
and of h = 10 T1 (far beyond any explicit stability limit).

The bound is asserted with SCHEME PRECISION EXTENDED: in double precision the internal forces
of a smooth field are rounded with an error ~ eps |K| |u|, which does work on the motion and
grows the balance like eps (omega_max / omega_1)^2 per step (docs/precision.md). The DOUBLE
runs are measured too, and the check asserts that EXTENDED is the more exact of the two, so
it shows what the extended evaluation buys.

Scenes and their first period T1:
- the cantilever of inputs/cantilever_release.dat (BEAM2, consistent mass, static preload):
  T1 = 1 / 8.3819 s (Euler-Bernoulli);
- plate.dat, QUAD4 plane strain, clamped left edge, initial velocity: T1 ~ 5.7e-3 s (beam
  estimate, see the file; only the order of magnitude matters for the choice of h);
- truss.dat, BAR2 truss with lumped mass, a spring-mass appendix, static preload and an initial
  velocity: T1 ~ 2 pi sqrt(m/k) of the appendix = 2.81e-3 s (the truss is much stiffer).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = 'tests/scenes/energy_linear/'
NSTEPS = 10000
RTOL = 1e-12
CASES = [
    ('cantilever', 'inputs/cantilever_release.dat', 1.0 / 8.3819),
    ('plate', HERE + 'plate.dat', 5.7e-3),
    ('truss', HERE + 'truss.dat', 2.0 * math.pi * math.sqrt(0.4 / 2e6)),
]

for name, scene, t1 in CASES:
    for label, h in [('T1/1000', t1 / 1000.0), ('10 T1', 10.0 * t1)]:
        common = ['TIME.STEP=%r' % h, 'TIME.END=%r' % (NSTEPS * h), 'OUTPUT.HISTORY=1', 'OUTPUT.FIELDS=0']
        out_double = sc.run_ok(scene, common + ['SCHEME.PRECISION=DOUBLE'])
        rel_double, _ = sc.relative_balance(out_double)
        out = sc.run_ok(scene, common + ['SCHEME.PRECISION=EXTENDED'])
        hist = sc.history(out)
        tag = '%s h=%s' % (name, label)
        rel_ext, _ = sc.relative_balance(out)
        print('# %s: DOUBLE max |balance| / max(kinetic + internal) = %.3e' % (tag, rel_double))
        sc.report(tag + ': EXTENDED at least as exact as DOUBLE', rel_ext <= rel_double,
                  'EXTENDED %.3e vs DOUBLE %.3e' % (rel_ext, rel_double))
        sc.report(tag + ': %d steps in history.csv' % NSTEPS, len(hist['step']) == NSTEPS + 1
                  and hist['step'][-1] == NSTEPS, '%d rows, last step %d' % (len(hist['step']), hist['step'][-1]))
        rel, _ = sc.relative_balance(out)
        print('# %s: EXTENDED max |balance| / max(kinetic + internal) = %.3e' % (tag, rel))
        sc.report(tag + ': |balance| <= 1e-12 x total energy', rel <= RTOL,
                  'measured %.3e vs expected <= %.0e' % (rel, RTOL))
        # The scene must really move: the energy is exchanged between kinetic and internal.
        e = hist['kinetic'] + hist['internal']
        moving = np.max(hist['kinetic']) > 0.1 * np.max(e) and np.max(hist['internal']) > 0.1 * np.max(e)
        sc.report(tag + ': energy exchanged between kinetic and internal', moving,
                  'max kinetic %.3e, max internal %.3e, max total %.3e'
                  % (np.max(hist['kinetic']), np.max(hist['internal']), np.max(e)))
        # No external forces in these scenes: the external work stays zero.
        sc.report(tag + ': no external work', np.all(hist['external'] == 0.0),
                  'max |external| %.3e' % np.max(np.abs(hist['external'])))
