"""FUNCTION kinds (issue 35, item 3; docs/input.md, "Functions"): POINTS, SINE, SMOOTH_STEP, TABLE FILE.

A spring-mass (k = 1000 N/m, m = 1 kg: f_n = 5.03 Hz):
- IMPOSE with a SINE (amplitude 0.01 m, 2 Hz, phase 30 degrees, from 0.1 to 0.6 s): the imposed
  displacement equals a sin(2π f (t - t0) + φ) on [t0, t1] and 0 outside, at every step (1e-15 m),
  the balance at round-off (the imposed motion's work booked);
- IMPOSE with a SMOOTH_STEP (from 0.2 to 0.7 s): ξ³(10 - 15ξ + 6ξ²) at every step, the velocity of
  the base continuous (C²: no jump from one step to the next beyond the step's own change);
- a LOAD F0 sin(Ωt) from rest (2 Hz): the mass's displacement against the exact undamped response
  F0/k/(1 - r²) (sin Ωt - r sin ω_n t), within 1e-4 of its amplitude at h = 1e-4 s (Newmark's
  error, second order: 4 times smaller at h/2);
- TABLE FILE: the same force read from a CSV of 19 999 rows (a header line, commas) gives the
  SINE's response within 1e-5 (the table's linear interpolation), and a table file of the POINTS of
  an inline function gives the same run bit for bit.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

BASE = """NODE a AT 0 0
NODE b AT 1 0
ELEMENT s TYPE SPRING NODES a b
ELEMENT m TYPE MASS NODES b
MATERIAL k ELASTIC YOUNG 1000
SECTION pm MASS 1
MODEL s MATERIAL k
MODEL m SECTION pm
FIX a UY
FIX b UY
"""
IMPOSE = """IMPOSE a UX VALUE %s FUNCTION w
TIME STEP 1e-3 END 1
OUTPUT HISTORY EVERY 1 PROBE a UX PROBE a VX
"""
IMPOSED = sc.write_scene('imposed.dat', BASE + 'FUNCTION w SINE AMPLITUDE 0.01 FREQUENCY 2 PHASE 30 START 0.1 END 0.6\n' +
                         IMPOSE % '1')
out = sc.run_ok(IMPOSED)
p = sc.probes(out)
t = p['time']
u = p['a.UX']
ex = np.where((t >= 0.1) & (t <= 0.6), 0.01 * np.sin(2 * np.pi * 2 * (t - 0.1) + np.pi / 6), 0.0)
sc.report_measured('SINE (START, END, PHASE): the imposed displacement at every step (1e-15 m)',
                   np.max(np.abs(u - ex)) <= 1e-15, '%.1e m' % np.max(np.abs(u - ex)))
bal, _ = sc.relative_balance(out)
sc.report_measured('SINE: |balance| <= 1e-10 of E', bal <= 1e-10, '%.1e' % bal)

out = sc.run_ok(sc.write_scene('step.dat', BASE + 'FUNCTION w SMOOTH_STEP T 0.7 START 0.2\n' + IMPOSE % '0.01'))
p = sc.probes(out)
t = p['time']
xi = np.clip((t - 0.2) / 0.5, 0, 1)
ex = 0.01 * xi ** 3 * (10 - 15 * xi + 6 * xi ** 2)
sc.report_measured('SMOOTH_STEP: ξ³(10 - 15ξ + 6ξ²) at every step (1e-15 m), 0.01 m from 0.7 s',
                   np.max(np.abs(p['a.UX'] - ex)) <= 1e-15 and p['a.UX'][-1] == 0.01, '%.1e m' % np.max(np.abs(p['a.UX'] - ex)))
dv = np.max(np.abs(np.diff(p['a.VX'])))
amax = 0.01 * 10 / np.sqrt(3) / 0.5 ** 2          # the largest base acceleration, at ξ = (3 - √3)/6
sc.report_measured('SMOOTH_STEP: the base velocity has no jump (each step changes it by at most 1.1 h max|a|)',
                   dv <= 1.1 * 1e-3 * amax, '%.3e m/s, h max|a| = %.3e m/s' % (dv, 1e-3 * amax))

# --- a sine force on the spring-mass: the exact forced response -----------------------------------------
F0, OM, WN = 2.0, 2 * np.pi * 2, np.sqrt(1000.0)
FORCE = """LOAD f NODES b FORCE 2 0 FUNCTION w
TIME STEP 1e-4 END 1
OUTPUT HISTORY EVERY 10 PROBE b UX
"""


def forced(fn, name):
    return sc.write_scene(name, BASE.replace('FIX a UY', 'FIX a ALL') + 'FUNCTION w ' + fn + '\n' + FORCE)


FORCED = forced('SINE AMPLITUDE 1 FREQUENCY 2', 'forced.dat')


def exact(t):
    r = OM / WN
    return F0 / 1000.0 / (1 - r * r) * (np.sin(OM * t) - r * np.sin(WN * t))


errs = {}
for h in (1e-4, 5e-5):
    p = sc.probes(sc.run_ok(FORCED, ['TIME.STEP=%g' % h]))
    errs[h] = np.max(np.abs(p['b.UX'] - exact(p['time']))) / np.max(np.abs(exact(p['time'])))
sc.report_measured('SINE force: the exact undamped response within 1e-4 of its amplitude at h = 1e-4 s',
                   errs[1e-4] <= 1e-4, '%.2e' % errs[1e-4])
sc.report_measured('SINE force: second order in h (error ratio 4 +- 0.4 at h/2)', abs(errs[1e-4] / errs[5e-5] - 4) <= 0.4,
                   '%.2f' % (errs[1e-4] / errs[5e-5]))

# --- TABLE FILE ----------------------------------------------------------------------------------------
tt = np.linspace(0, 1, 19999)        # (its points between the steps': interpolated)
csv = os.path.join(sc.TMP, 'sine.csv')
with open(csv, 'w') as f:
    f.write('time,value\n')
    for a, b in zip(tt, np.sin(OM * tt)):
        f.write('%.17g,%.17g\n' % (a, b))
ps = sc.probes(sc.run_ok(FORCED))
pt = sc.probes(sc.run_ok(forced('TABLE FILE ' + csv, 'forced_table.dat')))
d = np.max(np.abs(ps['b.UX'] - pt['b.UX'])) / np.max(np.abs(ps['b.UX']))
sc.report_measured('TABLE FILE (19 999 rows, header, commas): the SINE\'s response within 1e-5, not equal',
                   0 < d <= 1e-5, '%.1e' % d)
pts = [(0, 0), (0.1, 1), (0.25, -0.5), (0.6, 0.3), (1, 0)]
tab = os.path.join(sc.TMP, 'points.txt')
with open(tab, 'w') as f:
    f.write('# a comment\n\n' + ''.join('%r ; %r\n' % q for q in pts))
pi = sc.probes(sc.run_ok(forced('POINTS ' + ' '.join('%r %r' % q for q in pts), 'forced_points.dat')))
pf = sc.probes(sc.run_ok(forced('TABLE FILE ' + tab, 'forced_points_file.dat')))
sc.report('TABLE FILE of an inline function\'s POINTS (blanks, semicolons, a comment): the same run bit for bit',
          np.array_equal(pi['b.UX'], pf['b.UX']))
