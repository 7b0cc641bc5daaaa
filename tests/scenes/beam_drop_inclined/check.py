"""inputs/beam_drop_inclined.dat: an inclined steel beam (slope 1/10) dropped on a rigid ground.

In IMPACT PAPER and PERSIST over the scene's 2 s (h = 1e-5 s):
- total energy kinetic + strain + gravity potential constant: gravity is the only external
  force, so its work is minus the change of potential and balance = (kinetic + internal +
  potential) - initial; |balance| <= 1e-10 x max(kinetic + internal) over the whole run;
- at least 20 bounces: flights where every contact is open for more than 2 ms (from the
  active_contacts column, written every 10 steps);
- it keeps bouncing: >= 20 establish events, some in every tenth of the run after the first
  impact, and the mean kinetic energy of the last quarter of the run is at least half that
  of the second quarter (undamped linear elasticity: the energy stays in the beam's motion
  and vibration, it is not lost).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

SCENE = 'inputs/beam_drop_inclined.dat'

for mode in ['PAPER', 'PERSIST']:
    tag = 'beam_drop_inclined %s' % mode
    out = sc.run_ok(SCENE, ['SCHEME.IMPACT=' + mode, 'OUTPUT.FIELDS=0'])
    cc.check_balance(tag, out)
    hist = sc.history(out)
    t, act, kin = hist['time'], hist['active_contacts'], hist['kinetic']
    # Flights: maximal runs of rows with no active contact.
    flights = 0
    i = 0
    while i < len(t):
        if act[i] == 0:
            j = i
            while j < len(t) and act[j] == 0:
                j += 1
            if t[j - 1] - t[i] > 2e-3 and i > 0:
                flights += 1
            i = j
        else:
            i += 1
    ev = cc.events(out)
    est = np.array([e[1] for e in ev if e[3] == 'establish'])
    t_end = t[-1]
    t0 = est[0] if len(est) else t_end
    bins = np.histogram(est, bins=10, range=(t0, t_end))[0] if len(est) else np.zeros(10)
    q2 = np.mean(kin[(t >= t_end / 4) & (t < t_end / 2)])
    q4 = np.mean(kin[t >= 3 * t_end / 4])
    print('# %s: %d flights > 2 ms, %d establish events (per tenth of the run after the first impact: %s), '
          'mean kinetic 2nd quarter %.4f J, last quarter %.4f J'
          % (tag, flights, len(est), list(bins), q2, q4))
    sc.report(tag + ': at least 20 bounces', flights >= 20, '%d flights > 2 ms' % flights)
    sc.report(tag + ': >= 20 establish events spread over the run', len(est) >= 20 and np.all(bins > 0),
              '%d events, per tenth %s' % (len(est), list(bins)))
    sc.report(tag + ': kinetic energy not decaying', q4 >= 0.5 * q2, 'last quarter %.4f J vs second %.4f J' % (q4, q2))
