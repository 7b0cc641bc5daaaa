"""KINEMATICS LARGE for BEAM2: the corotational Euler-Bernoulli beam (issue 15, items 1, 2, 5 and 6).
docs/large-displacements.md.

- elastica.dat: the static elastica of a cantilever under a dead tip load at P L^2/EI = 1, 2, 5,
  10: the tip within 0.5 % of L of the exact elastica (integrated here by shooting, numpy RK4)
  and of Mattiasson's published table (measured: 0.04 %).
- spinning.dat: a free beam spinning at 1 rev/s: angular and linear momentum and energy kept
  (1e-10).
- inputs/beam_flying.dat (Simo and Vu-Quoc's free flying beam): |balance| <= 1e-10 of E for h from
  T/1000 to T/10; after the pulse the linear momentum is the impulse (20, 0) N s to 1e-10 (the
  trapezoidal rule's on the step grid, within 2e-5 of 20 where the hat's kinks fall between steps); the
  angular momentum is kept to 1e-10 at every h (the rotations turn by the Cayley angle of their
  increments and the step force has no moment: docs/large-displacements.md). ENERGY_CORRECTION OFF
  at T/10 loses > 10 % of E.
- inputs/cantilever_large.dat: held at P L^2/EI = 5, the tip at Mattiasson's 0.71379 L, 0.38763 L
  within 0.5 %; released, it swings to the other side (tip above the axis); |balance| <= 1e-10
  for h from T1/1000 to T1/10; OFF blows up (exit 1 or |balance| > 1e-2) at T1/10.
- inputs/beam_drop_inclined_large.dat: the 45-degree beam dropped on the ground: |balance| <= 1e-10
  for h = T/10, T/100 and T/1000 of its first bending mode, the first contact at sqrt(2 x 0.02/g),
  the ground never crossed (1e-9 m), the upper end reaching the ground.
- plastic_flop.dat: fibre-section plasticity at large rotation: |balance| <= 1e-10 with the
  plastic work (> 50 % of the launch energy dissipated), the tip turned by > 0.3 rad.
- small_amplitude.dat: LARGE = SMALL to 1e-6 of the motion at small amplitude.
- A restart of beam_flying continues bit for bit.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
FLY = 'inputs/beam_flying.dat'
CANT = 'inputs/cantilever_large.dat'
DROP = 'inputs/beam_drop_inclined_large.dat'
# Mattiasson (1981), cantilever under a dead tip load: P L^2/EI -> (deflection, shortening) / L.
MATTIASSON = {1: (0.30172, 0.05643), 2: (0.49346, 0.16064), 5: (0.71379, 0.38763), 10: (0.81061, 0.55500)}


def rel_balance(h):
    return np.max(np.abs(h['balance'])) / np.max(h['kinetic'] + h['internal'])


def elastica_tip(k2, n=2000):
    """Tip (deflection, shortening)/L of the inextensible elastica EI phi'' = -P cos(phi), phi(0) = 0,
    phi'(L) = 0 (L = EI = 1, P = k2), by shooting on phi'(0) with RK4."""
    def shoot(kappa0):
        y = np.array([0.0, kappa0, 0.0, 0.0])  # phi, phi', x, w
        ds = 1.0 / n

        def f(y):
            return np.array([y[1], -k2 * np.cos(y[0]), np.cos(y[0]), np.sin(y[0])])
        for _ in range(n):
            a = f(y)
            b = f(y + 0.5 * ds * a)
            c = f(y + 0.5 * ds * b)
            d = f(y + ds * c)
            y = y + ds / 6 * (a + 2 * b + 2 * c + d)
        return y
    lo, hi = 0.0, k2  # phi'(L) is positive at lo, negative at hi (the moment at the root is < P L)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if shoot(mid)[1] > 0:
            hi = mid
        else:
            lo = mid
    y = shoot(0.5 * (lo + hi))
    return y[3], 1.0 - y[2]


# --- the static elastica ---------------------------------------------------------------------
p = sc.probes(sc.run_ok(os.path.join(HERE, 'elastica.dat')))
for k2, t in ((1, 20), (2, 40), (5, 60), (10, 80)):
    i = np.argmin(np.abs(p['time'] - t))
    w, s = -p['beam.end.UY'][i], -p['beam.end.UX'][i]
    we, se = elastica_tip(k2)
    mw, ms = MATTIASSON[k2]
    err = max(abs(w - we), abs(s - se))
    sc.report('elastica P L^2/EI = %d: tip within 0.5 %% of L of the exact elastica' % k2, err <= 5e-3,
              'w %.5f s %.5f, exact %.5f %.5f' % (w, s, we, se))
    sc.report('elastica P L^2/EI = %d: the shooting reference = Mattiasson\'s table (1e-4)' % k2,
              max(abs(we - mw), abs(se - ms)) <= 1e-4, '%.5f %.5f vs %.5f %.5f' % (we, se, mw, ms))

# --- the free spinning beam ------------------------------------------------------------------
sc.free_body('spinning beam', sc.history(sc.run_ok(os.path.join(HERE, 'spinning.dat'))), 1e-12)

# --- the flying beam, h from T/10 to T/1000 ------------------------------------------------------
T = 1.256
for div in (10, 100, 1000):
    h = sc.history(sc.run_ok(FLY, ['TIME.STEP=%.6g' % (T / div)]))
    bal = rel_balance(h)
    sc.report('beam_flying h = T/%d: |balance| <= 1e-10 of E' % div, bal <= 1e-10, '%.2e' % bal)
    post = h['time'] >= 5.0 - 1e-9
    px, py = h['momentum_x'][post], h['momentum_y'][post]
    # The scheme's impulse: the trapezoidal rule of F on its step grid (20 N s when the hat's
    # kinks at 2.5 and 5 s fall on steps).
    hh = T / div
    tg = np.arange(0.0, 5.0 + 2 * hh, hh)
    fx = 8 * np.interp(tg, [0, 2.5, 5, 100], [0, 1, 0, 0])
    imp = np.sum(0.5 * hh * (fx[:-1] + fx[1:]))
    sc.report('beam_flying h = T/%d: momentum after the pulse = the impulse (1e-10; 20 N s to %.0e)' % (div, abs(imp - 20) / 20),
              np.max(np.abs(px - imp)) <= 2e-9 and np.max(np.abs(py)) <= 2e-9,
              'px %.12f, impulse %.12f, |py| %.1e' % (px[-1], imp, np.max(np.abs(py))))
    am = h['angular_momentum'][post]
    drift = (am.max() - am.min()) / abs(am[0])
    sc.report('beam_flying h = T/%d: angular momentum after the pulse kept to 1e-10' % div, drift <= 1e-10,
              '%.1e of %.3f' % (drift, am[0]))
rc, err, out = sc.run(FLY, ['TIME.STEP=%.6g' % (T / 10), 'SCHEME.ENERGY_CORRECTION=OFF'])
bal = rel_balance(sc.history(out))
sc.report('beam_flying h = T/10, ENERGY_CORRECTION OFF: plain Newmark loses > 10 % of E', bal > 0.1, '%.2e' % bal)

# --- the cantilever bent and released ---------------------------------------------------------
T1 = 1.19
for div in (10, 100, 1000):
    out = sc.run_ok(CANT, ['TIME.STEP=%.6g' % (T1 / div)])
    h, p = sc.history(out), sc.probes(out)
    bal = rel_balance(h)
    sc.report('cantilever_large h = T1/%d: |balance| <= 1e-10 of E' % div, bal <= 1e-10, '%.2e' % bal)
    if div == 1000:
        hold = (p['time'] > 10) & (p['time'] <= 12)
        w, s = -np.mean(p['strip.end.UY'][hold]), -np.mean(p['strip.end.UX'][hold])
        sc.report('cantilever_large: held at P L^2/EI = 5, tip at Mattiasson\'s (0.71379, 0.38763) L (0.5 %)',
                  abs(w - 0.71379) <= 0.005 * 0.71379 and abs(s - 0.38763) <= 0.005 * 0.38763, '%.5f %.5f' % (w, s))
        free = p['time'] > 12.5
        sc.report('cantilever_large: released, the strip swings to the other side (tip above 0.6 L)',
                  np.max(p['strip.end.UY'][free]) > 0.6, 'max %.4f' % np.max(p['strip.end.UY'][free]))
rc, err, out = sc.run(CANT, ['TIME.STEP=%.6g' % (T1 / 10), 'SCHEME.ENERGY_CORRECTION=OFF'])
hoff = sc.history(out)
sc.report('cantilever_large h = T1/10, ENERGY_CORRECTION OFF: blows up (exit 1) or drifts > 1e-2',
          rc != 0 or rel_balance(hoff) > 1e-2, 'exit %d, balance %.2e' % (rc, rel_balance(hoff)))

# --- the 45-degree beam dropped on the ground -------------------------------------------------
Tb = 0.019
for div in (10, 100, 1000):
    out = sc.run_ok(DROP, ['TIME.STEP=%.6g' % (Tb / div)])
    h, p = sc.history(out), sc.probes(out)
    bal = rel_balance(h)
    sc.report('beam_drop_inclined_large h = T/%d: |balance| <= 1e-10 of E' % div, bal <= 1e-10, '%.2e' % bal)
    c = sc.contacts(out)
    gap = np.min(c['min_gap'])
    sc.report('beam_drop_inclined_large h = T/%d: the ground never crossed (1e-9 m)' % div, gap >= -1e-9,
              'min gap %.2e m' % gap)
    if div == 100:
        with open(os.path.join(out, 'events.csv')) as f:
            f.readline()
            t0 = float(f.readline().split(',')[1])
        sc.report('beam_drop_inclined_large: first contact at sqrt(2 x 0.02 / g) = 0.06386 s (one step)',
                  abs(t0 - np.sqrt(0.04 / 9.81)) <= Tb / div, '%.5f s' % t0)
        top = 0.7271067811865476 + np.min(p['beam.end.UY'])
        sc.report('beam_drop_inclined_large: the upper end comes down to the ground (1 mm)', top <= 1e-3,
                  'lowest %.2e m' % top)

# --- plasticity at large rotation -------------------------------------------------------------
h, p = sc.history(sc.run_ok(os.path.join(HERE, 'plastic_flop.dat'))), None
bal = rel_balance(h)
sc.report('plastic flop: |balance| <= 1e-10 of E with the plastic work', bal <= 1e-10, '%.2e' % bal)
frac = h['dissipated'][-1] / h['kinetic'][0]
sc.report('plastic flop: > 50 % of the launch energy dissipated', frac > 0.5, '%.3f' % frac)
p = sc.probes(sc.run_ok(os.path.join(HERE, 'plastic_flop.dat')))
sc.report('plastic flop: the tip turned by > 0.3 rad', np.max(p['beam.end.RZ']) > 0.3, '%.3f rad' % np.max(p['beam.end.RZ']))

# --- small amplitude: LARGE = SMALL -------------------------------------------------------------
SMALL = os.path.join(HERE, 'small_amplitude.dat')
pl = sc.probes(sc.run_ok(SMALL))
ps = sc.probes(sc.run_ok(SMALL, ['MODEL.beam.KINEMATICS=SMALL']))
diff = max(np.max(np.abs(pl[k] - ps[k])) / np.max(np.abs(ps[k])) for k in ps if k != 'time')
sc.report('cantilever at small amplitude: LARGE = SMALL to 1e-6', diff <= 1e-6, '%.2e' % diff)

# --- restart bit for bit ----------------------------------------------------------------------
sets = ['OUTPUT.CHECKPOINT=100', 'TIME.END=8']
full = sc.run_ok(FLY, sets)
part = sc.new_dir('beam_part')
rc, err, _ = sc.run(FLY, sets[:1] + ['TIME.END=4'], outdir=part)
cmd = [sc.REBOND, FLY, '-o', part, '--quiet', '--restart', os.path.join(part, 'checkpoint.h5'), '--set', sets[0],
       '--set', sets[1]]
r = sc.run_limited(cmd, 120, cwd=sc.ROOT, capture_output=True, text=True)
same = all(open(os.path.join(full, f), 'rb').read() == open(os.path.join(part, f), 'rb').read()
           for f in ('history.csv', 'probes.csv'))
sc.report('beam_flying: restart at t = 4 s, history and probes bit for bit', rc == 0 and r.returncode == 0 and same,
          'exit %d, %d: %s' % (rc, r.returncode, r.stderr[-200:]))
