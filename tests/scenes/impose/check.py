"""IMPOSE (prescribed motion, src/time/imposed_motion.f90): a mass m = 2 kg on a spring k = 800 N/m
whose base is driven by IMPOSE base UX VALUE A FUNCTION sine, u_b = A sin(w t), A = 0.01 m,
w = 0.7 wn, from rest. The scene (base_driven.dat) is written here with its FUNCTION table every
1e-4 s (its interpolation error, A w^2 dt^2 / 8 = 2.5e-9 m, is far below the scheme's).
Exact: x = A wn^2/(wn^2 - w^2) (sin w t - (w/wn) sin wn t). Asserted:
- the base follows A f(t) (the table) at every step (1e-15 m: the multiplier holds the equality);
- the mass's response within 1e-3 of the amplitude at h = 1e-3 s, and the error falls as h^2
  (ratio 4 +- 10 % from h = 1e-3 to 5e-4 to 2.5e-4 s: the trapezoidal rule's order);
- PROBE base RX, the imposed DOF's reaction (half the step multiplier), equals the step mean
  of the spring force k (u_b - x) on the massless base (1e-12);
- the balance <= 1e-10 x the external work, which now holds the work of the imposed motion
  (about 0.3 J here, without it the balance would be that large).
push.dat: a bar pushed by IMPOSE into a rigid wall (an equality and a unilateral row in one
multiplier system), damped to rest: 100 N at both ends (0.1 %), the end at the wall, the balance
with the imposed motion's work.
Bad input (tests/scenes/bad_input): IMPOSE on a fixed DOF, on a DOF the node does not carry,
without FUNCTION, with two DOFs.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

M, K, A = 2.0, 800.0, 0.01
WN = math.sqrt(K / M)
W = 0.7 * WN
T_END = 2.0


TT = np.arange(0.0, T_END + 1e-9, 1e-4)


def scene():
    pts = ' '.join('%.17g %.17g' % (t, math.sin(W * t)) for t in TT)
    return '\n'.join([
        'TITLE "Spring-mass driven at its base"',
        'NODE base AT 0 0', 'NODE top AT 1 0',
        'ELEMENT s TYPE SPRING NODES base top', 'ELEMENT pm TYPE MASS NODES top',
        'MATERIAL k ELASTIC YOUNG %g' % K, 'SECTION m2 MASS %g' % M,
        'MODEL s MATERIAL k', 'MODEL pm SECTION m2',
        'FIX base UY', 'FIX top UY',
        'FUNCTION sine POINTS ' + pts,
        'IMPOSE base UX VALUE %g FUNCTION sine' % A,
        'TIME STEP 1e-3 END %g' % T_END,
        'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE top UX base UX base RX']) + '\n'


path = sc.write_scene('base_driven.dat', scene())
errs = []
for h in [1e-3, 5e-4, 2.5e-4]:
    out = sc.run_ok(path, ['TIME.STEP=%g' % h])
    p = sc.probes(out)
    hist = sc.history(out)
    t = p['time']
    exact = A * WN**2 / (WN**2 - W**2) * (np.sin(W * t) - W / WN * np.sin(WN * t))
    errs.append(np.abs(p['top.UX'] - exact).max())
    base = np.abs(p['base.UX'] - A * np.interp(t, TT, np.sin(W * TT))).max()
    sc.report('h = %g: the base follows the imposed A f(t) (1e-15 m)' % h, base <= 1e-15, 'error %.3e' % base)
    bal = np.abs(hist['balance']).max() / np.abs(hist['external']).max()
    sc.report('h = %g: |balance| <= 1e-10 x the external work (imposed motion booked)' % h, bal <= 1e-10,
              '%.3e (external %.3e J)' % (bal, np.abs(hist['external']).max()))
    print('# h = %g: max |x - exact| = %.4e m (amplitude %.4e m)' % (h, errs[-1], np.abs(exact).max()))
    f = K * (p['base.UX'] - p['top.UX'])           # the spring's pull on the massless base
    rerr = np.abs(p['base.RX'][1:] - 0.5 * (f[1:] + f[:-1])).max() / np.abs(f).max()
    sc.report('h = %g: PROBE base RX = the step mean of k (u_b - x) (1e-12)' % h, rerr <= 1e-12, '%.3e' % rerr)
sc.report('response within 1e-3 of the amplitude at h = 1e-3', errs[0] <= 1e-3 * 0.0332, '%.3e' % errs[0])
for i in range(2):
    r = errs[i] / errs[i + 1]
    sc.report('error ratio %d: %.3f = 4 (order 2) +- 10 %%' % (i + 1, r), abs(r / 4 - 1) <= 0.1, '%.4f' % r)

# push.dat: IMPOSE and a contact in one multiplier system (an equality and a unilateral row).
out = sc.run_ok(os.path.join(os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT), 'push.dat'))
p = sc.probes(out)
c = sc.contacts(out)
hist = sc.history(out)
sc.close('push: the imposed end carries EA/L x 1 mm = 100 N at rest (0.1 %)', p['bar.start.RX'][-1], 100.0, 1e-3)
sc.close('push: the wall pushes back 100 N (0.1 %)', -c['force_x'][-1], 100.0, 1e-3)
sc.report('push: the bar end never passes the wall (UX <= 1 mm + 1e-12 m) and rests on it',
          p['bar.end.UX'].max() <= 0.001 + 1e-12 and abs(p['bar.end.UX'][-1] - 0.001) <= 1e-12,
          'max %.15e, last %.15e' % (p['bar.end.UX'].max(), p['bar.end.UX'][-1]))
bal = np.abs(hist['balance']).max() / np.abs(hist['external']).max()
sc.report('push: |balance| <= 1e-10 x the external work', bal <= 1e-10, '%.3e' % bal)
