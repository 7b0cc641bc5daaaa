"""Single-DOF oscillator: the period of the trapezoidal rule (Newmark beta = 1/4, gamma = 1/2).

For m u'' + k u = 0 the scheme's solution is exactly u_n = A cos(Omega n h + phi) with
Omega h = 2 arctan(omega h / 2), for every h (no stability limit, period elongation only).
Omega is recovered from the three-term recurrence cos(Omega h) = (u_{n-1} + u_{n+1}) / (2 u_n),
at the samples of largest |u_n| (where round-off in u_n matters least).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

SCENE = 'tests/scenes/sdof_period/sdof.dat'
K, M = 8.0, 2.0                      # YOUNG of the spring (N/m) and SECTION MASS (kg) in sdof.dat
OMEGA = math.sqrt(K / M)
T = 2.0 * math.pi / OMEGA
NSTEPS = 200
NSAMPLES = 5                         # recurrence evaluated at the 5 samples of largest |u_n|


def numerical_period(u, h):
    """Periods 2 pi / Omega from the recurrence at the NSAMPLES interior samples of largest |u|."""
    inner = np.arange(1, len(u) - 1)
    best = inner[np.argsort(-np.abs(u[inner]))[:NSAMPLES]]
    c = (u[best - 1] + u[best + 1]) / (2.0 * u[best])
    return 2.0 * math.pi * h / np.arccos(c)


for label, frac in [('T/100', 0.01), ('T/10', 0.1), ('T/3', 1.0 / 3.0), ('T/2', 0.5), ('T', 1.0), ('2T', 2.0)]:
    h = frac * T
    out = sc.run_ok(SCENE, ['TIME.STEP=%r' % h, 'TIME.END=%r' % (NSTEPS * h)])
    p = sc.probes(out)
    u = p['tip.UX']
    sc.report('h=%s: %d steps written' % (label, NSTEPS), len(u) == NSTEPS + 1,
              '%d rows vs expected %d' % (len(u), NSTEPS + 1))
    sc.close('h=%s: initial displacement' % label, u[0], 0.1, 1e-15)
    expected = 2.0 * math.pi * h / (2.0 * math.atan(OMEGA * h / 2.0))
    periods = numerical_period(u, h)
    worst = periods[np.argmax(np.abs(periods - expected))]
    sc.close('h=%s: period 2 pi h / (2 atan(omega h / 2))' % label, worst, expected, 1e-10)
    if label == 'T/10':
        # The elongation is real and measurable: the test could tell a wrong scheme (e.g. an exact
        # integrator or a central-difference scheme) from the trapezoidal rule.
        elong = worst / T - 1.0
        sc.report('h=T/10: period elongation > 1e-3 (trapezoidal rule, not exact)', elong > 1e-3,
                  'measured T_num/T - 1 = %.3e, expected %.3e' % (elong, expected / T - 1.0))
    # Energy: the amplitude of the discrete solution is constant (no numerical damping).
    amp = np.max(np.abs(u))
    sc.report('h=%s: no amplitude decay (max |u| <= u0)' % label, amp <= 0.1 * (1 + 1e-12),
              'max |u| = %.17g vs u0 = 0.1' % amp)
