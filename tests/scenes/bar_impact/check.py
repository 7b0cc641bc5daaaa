"""inputs/bar_impact.dat: a free elastic bar hits a rigid wall at v0 = 1 m/s.

Exact (method.md section 4): the contact lasts 2 L / c and the bar leaves with the rigid
velocity -v0. Mesh and step of the scene: 100 lumped BAR2 elements, h = 1e-6 s (c h / dx =
0.52). Measured:
- contact duration: from the first `establish` to the last `release` of the impact in
  events.csv (+-h each), within 2 % of 2 L / c in PAPER and PERSIST;
- rebound velocity: slope of the centre-of-mass displacement after the last release (a free
  bar: the centre of mass moves exactly linearly, least squares over the fields samples,
  every 5 steps), within 3 % of v0 in PAPER and PERSIST;
- contact onsets: PERSIST keeps the contact, one `establish` for the impact; PAPER reflects
  the contact node at every closure and chatters (counts reported, not asserted);
- energy: |balance| <= 1e-10 x total energy in PAPER and PERSIST.
IMPACT OFF (plain Newmark with exact contact) is measured for comparison, not asserted.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

SCENE = 'inputs/bar_impact.dat'
E, RHO, L, V0 = 2.1e11, 7800.0, 1.0, 1.0       # as in the scene file
T_EXACT = 2.0 * L / math.sqrt(E / RHO)

for mode in ['PAPER', 'PERSIST', 'OFF']:
    tag = 'bar_impact %s' % mode
    out = sc.run_ok(SCENE, ['SCHEME.IMPACT=' + mode])
    ev = cc.events(out)
    est = [e for e in ev if e[3] == 'establish']
    rel = [e for e in ev if e[3] == 'release']
    if not est or not rel:
        sc.report(tag + ': the bar hits and leaves the wall', False, '%d establish, %d release' % (len(est), len(rel)))
        continue
    dur = rel[-1][1] - est[0][1]
    t, u, v = cc.line_com(out)
    after = t > rel[-1][1] + 1e-12
    slope = np.polyfit(t[after], u[after], 1)[0] if np.count_nonzero(after) >= 2 else np.nan
    hist = sc.history(out)
    print('# %s: %d establish events, contact %.6e s (2L/c = %.6e, ratio %.5f), rebound velocity %.6f m/s '
          '(ratio %.5f), final kinetic %.6f J internal %.3e J (initial kinetic %.6f J)'
          % (tag, len(est), dur, T_EXACT, dur / T_EXACT, slope, slope / V0, hist['kinetic'][-1],
             hist['internal'][-1], hist['kinetic'][0]))
    if mode == 'OFF':
        rel_off, _ = sc.relative_balance(out)
        print('# %s: max |balance| / total energy = %.3e (energy lost by the scheme at closure)' % (tag, rel_off))
        continue
    cc.check_balance(tag, out)
    sc.close(tag + ': contact duration = 2L/c within 2 %', dur, T_EXACT, 0.02)
    sc.close(tag + ': rebound velocity = v0 within 3 %', slope, V0, 0.03)
    if mode == 'PERSIST':
        sc.report(tag + ': one contact onset for the impact', len(est) == 1, '%d establish events' % len(est))
