"""The correction force of eq (9) is exactly zero where the path is straight in stress.

- Linear elastic models: sigma_bar is the chord midpoint and sigma_c = 0 bit for bit
  (docs/materials.md), so the correction column of history.csv is exactly 0.0 at every step:
  inputs/cantilever_release.dat (BEAM2, 2000 steps) and its ITERATION TANGENT variant.
- Elastoplastic scenes that never yield: a step whose elastic trial stays inside the yield
  surface is not sub-incremented (nused = 0, sigma_c = 0 bit for bit): correction and
  dissipated exactly 0.0 at every step, for fixed N and AUTO. inputs/spring_plastic.dat with
  v0 = 0.1 m/s (peak force v0 sqrt(k m) = 10 N < Fy = 100 N) and inputs/cantilever_plastic.dat
  (fibre section) with a tip velocity of 0.03 m/s (1 % of the yielding one: peak moment about
  about 1 % of the first-yield moment).
- Sanity: the same scenes at their yielding speed do give a nonzero correction.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

CASES = [
    ('cantilever_release (linear)', 'inputs/cantilever_release.dat', ['TIME.END=0.2'], False),
    ('cantilever_release (linear, TANGENT)', 'inputs/cantilever_release.dat',
     ['TIME.END=0.05', 'SCHEME.ITERATION=TANGENT'], False),
    ('spring_plastic v0=0.1, N=100', 'inputs/spring_plastic.dat',
     ['INITIAL.tip.VELOCITY=0.1 0', 'OUTPUT.FIELDS=0'], True),
    ('spring_plastic v0=0.1, AUTO', 'inputs/spring_plastic.dat',
     ['INITIAL.tip.VELOCITY=0.1 0', 'MODEL.spring.SUBSTEPS=AUTO', 'OUTPUT.FIELDS=0'], True),
    ('cantilever_plastic tip 0.03 m/s', 'inputs/cantilever_plastic.dat',
     ['INITIAL.beam.end.VELOCITY=0 0.03', 'TIME.END=0.3', 'OUTPUT.FIELDS=0'], True),
]
for name, scene, sets, plastic in CASES:
    h = sc.history(sc.run_ok(scene, sets))
    nz = int(np.count_nonzero(h['correction']))
    sc.report('%s: correction exactly 0.0 at every step (%d steps)' % (name, len(h['step']) - 1), nz == 0,
              '%d nonzero, max |correction| %.3e' % (nz, np.max(np.abs(h['correction']))))
    if plastic:
        sc.report('%s: dissipated exactly 0.0 at every step' % name, np.all(h['dissipated'] == 0.0),
                  'max %.3e' % np.max(np.abs(h['dissipated'])))
    e = h['kinetic'] + h['internal']
    sc.report('%s: the scene moves (max kinetic > 10 %% of the energy)' % name, np.max(h['kinetic']) > 0.1 * np.max(e))

# Sanity: at the yielding speed the correction is active.
for name, scene, sets in [('spring_plastic v0=3', 'inputs/spring_plastic.dat', ['OUTPUT.FIELDS=0']),
                          ('cantilever_plastic', 'inputs/cantilever_plastic.dat', ['TIME.END=0.1', 'OUTPUT.FIELDS=0'])]:
    h = sc.history(sc.run_ok(scene, sets))
    sc.report('%s: yields and the correction works (nonzero)' % name,
              np.max(h['dissipated']) > 0 and np.count_nonzero(h['correction']) > 0,
              'dissipated %.3e, correction %.3e' % (np.max(h['dissipated']), np.max(np.abs(h['correction']))))
