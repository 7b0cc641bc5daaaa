"""Fibre-section BEAM2 cantilever under a slow end-moment ramp (moment.dat): the structural
moment-rotation curve against the closed-form elastic-perfectly-plastic rectangle.

The moment M is uniform along the beam, so the curvature kappa is too (exactly representable by
the Hermite cubics) and the tip rotation is theta = kappa L. Closed form (continuum section):
  elastic  theta = M L / EI                      for M <= M_e
  plastic  kappa = kappa_e / sqrt(3 - 2 M/M_e)   for M_e < M < M_p = 1.5 M_e, collapse at M_p.
The n-layer midpoint section has EI (1 - 1/n^2) exactly, and an elastic-plastic curve that
converges to the closed form as O(1/n^2) (tests/unit/test_beam_fibre.f90 at the kernel level).
The ramp (smooth start, 4 s, first period ~ 12 ms) is quasi-static up to a small residual
vibration. Asserted, for n = 10, 20, 40 layers (SUBSTEPS 1, ITERATION TANGENT: the collapse is
a load-controlled run-away that the elastic iteration matrix cannot follow):
- elastic slope: the least-squares slope of theta(M) over M <= 0.95 M_e equals L / (EI (1 - 1/n^2))
  to 1e-5 (measured ~2.5e-6: the residual vibration), i.e. the continuum L/EI to 1/(n^2 - 1) + 1e-5;
- plastic branch: max relative error of theta at M = 1.1, 1.2, 1.3, 1.4 M_e decreases with n
  and is <= 1 % with 40 layers (measured 4.7e-2, 7.6e-3, 3.8e-3 for 10, 20, 40);
- collapse: the moment at which theta first exceeds 10 theta_e (static closed form:
  0.9967 M_p) is within 1 % of M_p = 1.5 M_e.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

SCENE = 'tests/scenes/fibre_moment/moment.dat'
E, SY, B, H, L = 2.1e11, 2.5e8, 0.01, 0.01, 1.0
EI = E * B * H**3 / 12
ME = SY * B * H**2 / 6
MP = 1.5 * ME
KE = 2 * SY / (E * H)
MMAX = 1.6 * ME
A, TR = 0.5, 4.0 - 0.25          # the FUNCTION ramp of moment.dat


def ramp(t):
    return np.where(t < A, t**2 / (2 * A * TR), np.minimum((t - A / 2) / TR, 1.0))


perr = []
for n in (10, 20, 40):
    out = sc.run_ok(SCENE, ['SECTION.rect.LAYERS=%d' % n])
    p = sc.probes(out)
    t, th = p['time'], p['beam.end.RZ']
    m = MMAX * ramp(t)
    el = m <= 0.95 * ME
    slope = np.sum(th[el] * m[el]) / np.sum(m[el] ** 2)
    fib = L / (EI * (1 - 1.0 / n**2))
    sc.report('n=%d: elastic slope = L / (EI (1 - 1/n^2)) to 1e-5' % n, abs(slope / fib - 1) <= 1e-5,
              'measured %.3e' % (slope / fib - 1))
    sc.report('n=%d: elastic slope = L/EI to 1/(n^2 - 1) + 1e-5' % n, abs(slope * EI / L - 1) <= 1.0 / (n**2 - 1) + 1e-5,
              'measured %.3e' % (slope * EI / L - 1))
    errs = []
    for r in (1.1, 1.2, 1.3, 1.4):
        i = int(np.argmin(np.abs(m - r * ME)))
        errs.append(abs(th[i] / (L * KE / np.sqrt(3 - 2 * m[i] / ME)) - 1))
    perr.append(max(errs))
    ic = int(np.argmax(th > 10 * L * KE))
    mc = m[ic] / MP
    print('# n = %d: slope / (L/EI) - 1 = %.4e (1/(1-1/n^2) - 1 = %.4e); plastic branch max rel. error %.3e;'
          ' collapse at M = %.4f M_p' % (n, slope * EI / L - 1, 1 / (1 - 1.0 / n**2) - 1, perr[-1], mc))
    sc.report('n=%d: collapse (theta > 10 theta_e) within 1 %% of M_p' % n, th[ic] > 10 * L * KE and abs(mc - 1) <= 0.01,
              'M/M_p = %.4f' % mc)
sc.report('plastic branch error decreases with layers (10, 20, 40)', perr[0] > perr[1] > perr[2],
          ' > '.join('%.3e' % e for e in perr))
sc.report('plastic branch within 1 % of the closed form with 40 layers', perr[2] <= 0.01, '%.3e' % perr[2])
