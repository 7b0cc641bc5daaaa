"""inputs/cantilever_release.dat: the first validation scene.

- The initial state is the static response to a 1 N tip load: Euler-Bernoulli Hermite beams are
  exact at the nodes for nodal loads, so the tip deflection is F L^3 / (3 E I) and the mid-span
  deflection F x^2 (3 L - x) / (6 E I) at x = L/2, both to round-off (asserted to 1e-6 relative;
  the solve is ~1e-10 accurate given the conditioning of K).
- The free vibration is dominated by mode 1: its frequency, from the zero crossings of the tip
  deflection minus its mean (linear interpolation between samples), must match
  f1 = (1.875104068711961^2 / 2 pi) sqrt(E I / (rho A L^4)) = 8.3819 Hz within 0.5 %. Expected
  deviations: 20-element discretisation ~5e-8, period elongation of the scheme (omega h)^2 / 12 ~
  2e-6 at h = 1e-4 s, and the higher modes shifting individual crossings by < 0.1 % of a period
  averaged over the ~8 periods of the run (END set to 1 s).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

SCENE = 'inputs/cantilever_release.dat'
E, I, RHO, A, L, F = 2.1e11, 8.333333333e-10, 7800.0, 1e-4, 1.0, 1.0   # as in the scene file
F1 = 1.875104068711961**2 / (2.0 * math.pi) * math.sqrt(E * I / (RHO * A * L**4))


def upward_crossings(t, y):
    """Times where y crosses zero upwards, by linear interpolation between samples."""
    k = np.nonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))[0]
    return t[k] - y[k] * (t[k + 1] - t[k]) / (y[k + 1] - y[k])


out = sc.run_ok(SCENE, ['TIME.END=1.0', 'OUTPUT.FIELDS=0'])
p = sc.probes(out)
t, tip, mid = p['time'], p['beam.end.UY'], p['beam.mid.UY']

sc.close('initial tip deflection = -F L^3 / (3 E I)', tip[0], -F * L**3 / (3.0 * E * I), 1e-6)
x = 0.5 * L
sc.close('initial mid-span deflection = -F x^2 (3L - x) / (6 E I)', mid[0], -F * x**2 * (3 * L - x) / (6.0 * E * I), 1e-6)

# Mean over whole periods: first pass with the plain mean, second with the mean between the
# first and last upward crossings (a plain mean over a fractional number of periods is biased).
y = tip - np.mean(tip)
c = upward_crossings(t, y)
if len(c) >= 2:
    window = (t >= c[0]) & (t <= c[-1])
    y = tip - np.mean(tip[window])
    c = upward_crossings(t, y)
ok = len(c) >= 5
sc.report('tip response oscillates (>= 4 full periods)', ok, '%d upward zero crossings' % len(c))
if ok:
    f = (len(c) - 1) / (c[-1] - c[0])
    sc.close('dominant frequency of the tip = f1 (Euler-Bernoulli, 8.3819 Hz)', f, F1, 5e-3)
# Free vibration about the unloaded equilibrium. Upper bound, exact: a tip deflection d costs at
# least the strain energy 1/2 (3 E I / L^3) d^2 (the static shape minimises it, and the elements
# are exact at the nodes), and the total energy is 1/2 (3 E I / L^3) u0^2, so |d| <= |u0|. Lower
# bound, loose: mode 1 carries ~97 % of the static shape, so the tip swings back past 0.9 |u0|.
amp = np.max(tip)
sc.report('tip swings back to +0.9..1.0 x |u0|', 0.9 * abs(tip[0]) <= amp <= abs(tip[0]) * (1 + 1e-9),
          'max tip %.6e vs |u0| %.6e' % (amp, abs(tip[0])))
