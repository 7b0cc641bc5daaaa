"""Plastic impacts converge at the defaults on refined meshes (issue 38, item 1).

The Taylor bar of inputs/taylor_plane.dat refined to 8 x 40 (nothing else changed) stopped at every step
size before: Newton contracted by 0.6 per iteration in the impact's first steps (the tangent was the
end stress's, where eq (9) iterates 2 Bσ̄ - Bσ(n): law_step_t's dbar now) and stagnated at 69 µs at
1e-2 against a tolerance of 3.7e-3 (the secant stress of STRAIN_MEASURE LOG divided round-off by |ΔE|²:
secant_stress). Asserted at h = 5e-7 s (the other steps and 16 x 80 in `make bench`): the run reaches
80 µs with no retried step (history.csv substeps = 1 throughout), |balance| <= 1e-10 of E, more than
90 % of the energy dissipated; the mean iteration count is printed. inputs/block_j2.dat at twice its
mesh (40 x 20) runs at the defaults with no retried step and its balance at 1e-10.
The axisymmetric cylinder (inputs/taylor_bar.dat, 4 x 20 and 8 x 40 at h = 5e-7 s): Newton cycled
between two states at 31-43 µs (4 and 3 steps retried): a relaxed iterate after a rise of the residual
that follows a fall breaks the cycle (no retried step); and a crushed point's log map (P up to 1/λ²)
lost the secant's correction below |ΔE| = 2δ, leaving up to 3e-7 J in one step (2e-10 of E on 4 x 20
with the relaxed path, 1.6e-9 under IMPACT PAPER): kept now wherever its work stands above round-off
(secant_stress), |balance| <= 1e-10 of E.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

TAYLOR = os.path.join('inputs', 'taylor_plane.dat')
out = sc.run_ok(TAYLOR, ['RECTANGLE.ELEMENTS=8 40', 'TIME.STEP=5e-7', 'OUTPUT.FIELDS=EVERY 0'])
h = sc.history(out)
sc.report_measured('Taylor bar 8 x 40, h = 5e-7, defaults: reaches 80 us', abs(h['time'][-1] - 8e-5) < 1e-12,
                   't = %.3g' % h['time'][-1])
retried = int(np.sum(h['substeps'] > 1))
sc.report_measured('Taylor bar 8 x 40, h = 5e-7: no step retried as sub-steps', retried == 0, '%d retried' % retried)
bal = np.max(np.abs(h['balance'])) / h['kinetic'][0]
sc.report_measured('Taylor bar 8 x 40, h = 5e-7: |balance| <= 1e-10 of E', bal <= 1e-10, '%.2e' % bal)
diss = h['dissipated'][-1] / h['kinetic'][0]
sc.report_measured('Taylor bar 8 x 40, h = 5e-7: more than 90 % of E dissipated', diss > 0.9, '%.2f %%' % (100 * diss))
sc.report_measured('Taylor bar 8 x 40, h = 5e-7: mean Newton iterations per step (printed)', True,
                   '%.2f (max %d)' % (np.mean(h['iterations'][1:]), np.max(h['iterations'])))

out = sc.run_ok(os.path.join('inputs', 'block_j2.dat'), ['RECTANGLE.ELEMENTS=40 20', 'OUTPUT.FIELDS=EVERY 0'])
h = sc.history(out)
retried = int(np.sum(h['substeps'] > 1))
bal = np.max(np.abs(h['balance'])) / np.max(h['kinetic'] + h['internal'])
sc.report_measured('block_j2 at 40 x 20, defaults: no step retried, |balance| <= 1e-10', retried == 0 and bal <= 1e-10,
                   '%d retried, balance %.2e, %.2f iterations a step' % (retried, bal, np.mean(h['iterations'][1:])))

AXI = os.path.join('inputs', 'taylor_bar.dat')
for mesh in ['4 20', '8 40']:
    out = sc.run_ok(AXI, ['RECTANGLE.ELEMENTS=' + mesh, 'TIME.STEP=5e-7', 'OUTPUT.FIELDS=EVERY 0'])
    h = sc.history(out)
    retried = int(np.sum(h['substeps'] > 1))
    bal = np.max(np.abs(h['balance'])) / h['kinetic'][0]
    ok = abs(h['time'][-1] - 8e-5) < 1e-12 and bal <= 1e-10 and retried == 0
    sc.report_measured('axisymmetric Taylor bar %s, h = 5e-7, defaults: reaches 80 us, no step retried, |balance| <= '
                       '1e-10 of E' % mesh.replace(' ', ' x '), ok,
                       '%d retried, balance %.2e, %.2f iterations a step' % (retried, bal, np.mean(h['iterations'][1:])))
