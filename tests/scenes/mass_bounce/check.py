"""inputs/mass_bounce.dat: a point mass dropped from H = 1 m comes back to H after every bounce.

method.md section 4: with the impact corrections (10)-(16) the energy lost by the scheme at
each impact is given back exactly, so every apex is at H to round-off, for any step h. Five
steps not aligned with the impact times (t_f = sqrt(2H/g) = 0.451524 s, bounce period 2 t_f)
are run for 50 bounces (END 46 s) in IMPACT PAPER (PERSIST falls back to PAPER for a lone
point mass: it has no kinetic energy left after the projection; both are run).

Apex measurement, kinematic (independent of the energy accounting): between impacts Newmark
with a constant force is exact, the samples lie on a parabola of curvature -g, so at the
highest sample k of a flight the central difference v_k = (y(k+1) - y(k-1)) / 2h is the exact
velocity and the apex is y_k + v_k^2 / 2g. Bound: |apex - H| <= 1e-10 H for every one of the
50 apexes. Rounding of the probe (17 digits) gives ~1e-16 m on y_k and ~1e-13 m/s on v_k.
The energy way (y_k + kinetic_k / m g, from history.csv) is printed as a cross-check.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

SCENE = 'inputs/mass_bounce.dat'
H, M, G = 1.0, 1.0, 9.81                # as in the scene file
NB = 50
STEPS = [1.3e-3, 2.7e-3, 7.3e-4, 4.1e-3, 1.9e-3]

for h in STEPS:
    for mode in ['PAPER', 'PERSIST']:
        tag = 'mass_bounce h=%g %s' % (h, mode)
        out = sc.run_ok(SCENE, ['TIME.STEP=%r' % h, 'SCHEME.IMPACT=' + mode, 'OUTPUT.HISTORY=1'])
        cc.check_balance(tag, out)
        if mode == 'PERSIST':
            continue
        hist = sc.history(out)
        y = H + sc.probes(out)['ball.UY']
        act = hist['active_contacts']
        contact_steps = np.nonzero(act > 0)[0]
        # Flights: the samples from one contact step (its end state already reflected) to the
        # step before the next contact step lie on one parabola.
        bounds = list(contact_steps) + [len(y)]
        apex, apex_e = [], []
        for a, b in zip(bounds[:-1], bounds[1:]):
            if b - a < 3:
                continue
            k = a + 1 + int(np.argmax(y[a + 1:b - 1]))
            v = (y[k + 1] - y[k - 1]) / (2.0 * h)
            apex.append(y[k] + v * v / (2.0 * G))
            apex_e.append(y[k] + hist['kinetic'][k] / (M * G))
        apex = np.array(apex[:NB])
        ok = len(apex) == NB
        sc.report(tag + ': %d bounces with a complete flight after them' % NB, ok,
                  '%d flights, %d contact steps' % (len(apex), len(contact_steps)))
        err = np.max(np.abs(apex - H)) / H if len(apex) else np.inf
        err_e = np.max(np.abs(np.array(apex_e[:NB]) - H)) / H if len(apex_e) else np.inf
        print('# %s: max |apex - H| / H over %d apexes = %.3e (kinematic), %.3e (energy)'
              % (tag, len(apex), err, err_e))
        sc.report(tag + ': every apex at H within 1e-10 H', ok and err <= 1e-10,
                  'max |apex - H| / H = %.3e' % err)
