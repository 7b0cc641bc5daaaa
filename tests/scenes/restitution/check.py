"""RESTITUTION e (issue 11): Newton's law at contact establishment, normal velocity after = -e x
before, in the M-metric of eq (16); the kinetic energy it removes is booked in history.csv's
impact_dissipated, so the balance holds.

inputs/mass_bounce.dat (point mass dropped from H = 1 m) with OBSTACLE RESTITUTION e:
- e = 0.5: the apexes of the first bounces are e^(2k) H, i.e. the ratio of two successive
  apexes is e² = 0.25 to 1e-10, for h over four decades (1e-5 ... 1e-1 s, steps not aligned
  with the impact times); measured kinematically (the samples of a flight lie on a parabola);
- e = 0: the mass stays on the ground after the first impact (no flight, at rest);
- never a penetration beyond the tolerance; |balance| <= 1e-10 x total energy with
  impact_dissipated, which grows only at impacts and ends at m g H (e < 1: it all comes to rest).
Bad input (tests/scenes/bad_input): RESTITUTION outside [0, 1].
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

SCENE = 'inputs/mass_bounce.dat'
H, M, G = 1.0, 1.0, 9.81
TOL = 1e-12

for h in [1.3e-5, 1.1e-4, 1.3e-3, 1.7e-2, 0.093]:
    e = 0.5
    end = 3.5 if h < 1e-4 else 8.0
    tag = 'e=%g h=%g' % (e, h)
    out = sc.run_ok(SCENE, ['TIME.STEP=%r' % h, 'TIME.END=%r' % end, 'OBSTACLE.RESTITUTION=%r' % e, 'SCHEME.IMPACT=PAPER'])
    hist = sc.history(out)
    y = H + sc.probes(out)['ball.UY']
    cc.check_balance(tag, out)
    sc.report(tag + ': no penetration beyond the tolerance', y.min() >= -TOL, 'lowest %.3e m' % y.min())
    act = hist['active_contacts']
    contact_steps = np.nonzero(act > 0)[0]
    bounds = list(contact_steps) + [len(y)]
    apex = []
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b - a < 5:
            continue
        k = a + 1 + int(np.argmax(y[a + 1:b - 1]))
        v = (y[k + 1] - y[k - 1]) / (2.0 * h)
        apex.append(y[k] + v * v / (2.0 * G))
    apex = np.array(apex[:3])
    if h < 0.05:        # the coarsest step samples the second flight (0.23 s) only twice
        ok = len(apex) >= 2
        ratios = apex[1:] / apex[:-1] if ok else np.array([np.inf])
        sc.report(tag + ': successive apexes in the ratio e^2 = 0.25 (1e-10)',
                  ok and np.all(np.abs(ratios - e * e) <= 1e-10),
                  'apexes %s, ratios %s' % (np.array2string(apex, precision=12), np.array2string(ratios, precision=12)))
    sc.report(tag + ': a first flight measured', len(apex) >= 1)
    if len(apex) >= 1:
        sc.close(tag + ': first apex e^2 H (1e-10)', apex[0], e * e * H, 1e-10)

out = sc.run_ok(SCENE, ['TIME.STEP=1.3e-3', 'TIME.END=3', 'OBSTACLE.RESTITUTION=0'])
hist = sc.history(out)
y = H + sc.probes(out)['ball.UY']
first = int(np.nonzero(hist['active_contacts'] > 0)[0][0])
sc.report('e=0: stays on the ground after the first impact', np.all(np.abs(y[first:]) <= 1e-9) and
          np.all(hist['active_contacts'][first:] > 0), 'highest after impact %.3e m' % np.abs(y[first:]).max())
cc.check_balance('e=0', out)
sc.close('e=0: impact_dissipated = m g H (all the energy)', hist['impact_dissipated'][-1], M * G * H, 1e-9)
sc.report('e=0: kinetic energy zero on the ground', hist['kinetic'][first + 1:].max() <= 1e-20,
          'max %.3e J' % hist['kinetic'][first + 1:].max())
