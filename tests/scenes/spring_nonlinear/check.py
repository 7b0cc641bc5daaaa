"""Energy conservation of eq (9) on a nonlinear-elastic oscillator (inputs/spring_nonlinear.dat).

A 1 kg mass on a spring N(e) = k e (1 + b e^2), k = 100 N/m, b = 100 1/m^2, released from rest
at e0 = 0.1 m (b e0^2 = 1: strongly nonlinear); E = psi(e0) = 0.75 J, T = 2 pi sqrt(m/k) the
small-amplitude period. Over 1000 periods, for h = T/200, T/50, T/10, T/2, T, 2T:

- with the correction (eq 9), kinetic + W_N is conserved to the solver tolerance:
  max |balance| <= 1e-9 x total energy at every h;
- without it (SCHEME ENERGY_CORRECTION OFF, plain Newmark: the trapezoid work), the energy
  error max |balance| / E is at least 1e-4 at every h (measured over 100 periods) (it is bounded, not secular: the
  trapezoidal rule is time-reversible, so the lunules of the outward and return swings
  largely cancel; the maximum is reached within the first periods).

Settings needed for the 1e-9 bound (measured; the defaults do not reach it):
- SCHEME TOLERANCE 1e-14: the energy error of a step is 1/2 du.r (r the residual of eq 9), so
  the balance is tolerance-limited (default 1e-10: 3.5e-7 over 100 periods at T/200; 1e-13:
  1.7e-9 over 1000 periods at T/50);
- SCHEME ITERATION TANGENT: the elastic iteration matrix K0 + 4M/h^2 is too stiff-blind for
  h >= T/2 at this amplitude (tangent up to 4 k) and diverges;
- a fixed SUBSTEPS (16): with AUTO the sub-increment count depends on the iterate, the residual
  is discontinuous and the iteration can stall (TANGENT, TOLERANCE 1e-14, h = T/200: stuck at
  |r| = 8.8e-4 at step 31597);
- MAX_ITERATIONS 100: the tangent of the corrected system is not consistent (Bsigma_c is not
  differentiated), so convergence is linear for large h (up to ~50 iterations at h = 2T).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

SCENE = 'inputs/spring_nonlinear.dat'
T = 2.0 * math.pi * math.sqrt(1.0 / 100.0)
PERIODS = 1000
E0 = 100.0 * (0.1**2 / 2 + 100.0 * 0.1**4 / 4)      # psi(e0) = 0.75 J
ON = ['SCHEME.ITERATION=TANGENT', 'SCHEME.TOLERANCE=1e-14', 'SCHEME.MAX_ITERATIONS=100',
      'MODEL.spring.SUBSTEPS=16']
OFF = ['SCHEME.ITERATION=TANGENT', 'SCHEME.ENERGY_CORRECTION=OFF', 'MODEL.spring.SUBSTEPS=16']

for label, frac in [('T/200', 1 / 200.0), ('T/50', 1 / 50.0), ('T/10', 0.1), ('T/2', 0.5), ('T', 1.0), ('2T', 2.0)]:
    h = frac * T
    n = int(round(PERIODS / frac))
    common = ['TIME.STEP=%r' % h, 'TIME.END=%r' % (n * h), 'OUTPUT.HISTORY=1', 'OUTPUT.FIELDS=0']
    hist = sc.history(sc.run_ok(SCENE, common + ON))
    total = hist['kinetic'][0] + hist['internal'][0]
    rel_on = np.max(np.abs(hist['balance'])) / total
    print('# h = %s (%d steps): ON  max |balance| / E = %.3e (mean %.2f iterations per step)'
          % (label, n, rel_on, np.mean(hist['iterations'][1:])))
    # The initial internal energy is W_N of the path 0 -> e0, whose trapezoid error is exact:
    # (e0/N)^2 / 12 (N'(e0) - N'(0)) (docs/materials.md), N = 16.
    w0 = E0 + (0.1 / 16) ** 2 / 12 * (100.0 * (1 + 3 * 100.0 * 0.1**2) - 100.0)
    sc.report('h=%s: initial energy = psi(e0) + exact trapezoid error of W_16' % label,
              abs(total - w0) <= 1e-12 * w0, 'measured %.17g vs %.17g' % (total, w0))
    sc.report('h=%s: %d steps in history.csv' % (label, n), hist['step'][-1] == n, 'last step %d' % hist['step'][-1])
    sc.report('h=%s: with the correction |balance| <= 1e-9 x total energy over 1000 periods' % label,
              rel_on <= 1e-9, 'measured %.3e' % rel_on)
    sc.report('h=%s: the correction does work (max |correction| > 1e-6 E)' % label,
              np.max(np.abs(hist['correction'])) > 1e-6 * total, 'max %.3e' % np.max(np.abs(hist['correction'])))
    # OFF: the error is bounded and reached in the first periods; 100 periods are enough.
    noff = max(int(round(100 / frac)), 1)
    hoff = sc.history(sc.run_ok(SCENE, ['TIME.STEP=%r' % h, 'TIME.END=%r' % (noff * h), 'OUTPUT.FIELDS=0'] + OFF))
    rel_off = np.max(np.abs(hoff['balance'])) / total
    print('# h = %s: OFF max |balance| / E = %.3e' % (label, rel_off))
    sc.report('h=%s: without the correction the energy error is >= 1e-4' % label, rel_off >= 1e-4,
              'measured %.3e' % rel_off)
    sc.report('h=%s: OFF has no correction work' % label, np.all(hoff['correction'] == 0.0))
