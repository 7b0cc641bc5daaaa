"""Slow approaches never pass through (issue 11): a contact that starts inside the gap
tolerance and creeps further in, slower than the tolerance per step, is caught when the
penetration reaches the tolerance, at any speed.

creep_mass.dat: a point mass on the ground pushed in at 5e-10 m/s for 1e5 steps (h = 1e-3 s;
before the fix it ended 5e-8 m below the ground with no event). creep_pair.dat: two masses in
node-to-node contact closing at 2e-10 m/s (1e5 steps). Asserted at every step: penetration
<= the documented tolerance (1e-12 x model size, docs/contact.md), a contact event, and the
energy balance. With IMPACT PAPER the slow impact is elastic: the mass leaves at +5e-10 m/s.
held_lumped.dat: a lumped bar pushed against the wall for 10 000 steps at h = dx/c, where PAPER's
held node is marginal (docs/contact.md, Limits): in PAPER, PERSIST and MASSLESS the balance stays
<= 1e-12 of the energy at every step (measured 9e-14, 2e-14, 5e-14), an active condition's gap
stays closed (<= the tolerance) and the node never goes through the wall.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
TOL = 1.0e-12          # gap_rtol x model size (1 m: the bounding box, or 1 for a single node)

for mode in ['PAPER', 'PERSIST', 'OFF']:
    out = sc.run_ok(os.path.join(HERE, 'creep_mass.dat'), ['SCHEME.IMPACT=' + mode])
    uy = sc.probes(out)['ball.UY']
    h = sc.history(out)
    sc.report('creep_mass %s: 1e5 steps run' % mode, len(uy) == 100001, '%d rows' % len(uy))
    sc.report('creep_mass %s: penetration <= tolerance at every step' % mode, uy.min() >= -TOL * (1 + 1e-9),
              'deepest %.3e m (tolerance %.1e m)' % (-uy.min(), TOL))
    sc.report('creep_mass %s: the contact is established' % mode, h['active_contacts'].max() >= 1 or
              os.path.getsize(os.path.join(out, 'events.csv')) > 60)
    if mode != 'OFF':
        cc.check_balance('creep_mass ' + mode, out)

out = sc.run_ok(os.path.join(HERE, 'creep_pair.dat'))
p = sc.probes(out)
gap = 1.0 + p['b.UX'] - p['a.UX']
sc.report('creep_pair: 1e5 steps run', len(gap) == 100001, '%d rows' % len(gap))
sc.report('creep_pair: closure beyond contact <= tolerance at every step', gap.min() >= -TOL * (1 + 1e-9),
          'deepest %.3e m (tolerance %.1e m)' % (-gap.min(), TOL))
cc.check_balance('creep_pair PAPER', out)

for mode in ['PAPER', 'PERSIST', 'MASSLESS']:
    out = sc.run_ok(os.path.join(HERE, 'held_lumped.dat'), ['SCHEME.IMPACT=' + mode])
    c = sc.contacts(out)
    tol = TOL * 0.2                                   # gap_rtol x the bar's length
    sc.report('held_lumped %s: 10 000 steps run' % mode, len(c['min_gap']) == 10001, '%d rows' % len(c['min_gap']))
    held = c['min_gap'][c['active'] > 0]
    sc.report('held_lumped %s: an active condition stays closed' % mode, held.size > 0 and abs(held).max() <= tol,
              'largest |gap| while active %.3e m' % (abs(held).max() if held.size else np.nan))
    sc.report('held_lumped %s: never through the wall' % mode, c['min_gap'].min() >= -tol,
              'deepest %.3e m' % -c['min_gap'].min())
    rel, n = sc.relative_balance(out)
    sc.report('held_lumped %s: |balance| <= 1e-12 x energy at every step' % mode, rel <= 1e-12, 'measured %.3e' % rel)
