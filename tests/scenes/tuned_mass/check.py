"""MASS MIXED alpha: alpha x consistent + (1 - alpha) x lumped, and MASS TUNED, the mass tuned to the
step, alpha = 1/2 + (c h / dx)^2 on each element (docs/contact.md, "A mass tuned to the step").

Free vibration (modal_bar.dat: a bar fixed at both ends released from its first mode, c = L = 1):
- the midpoint's frequency, measured from the three-term recurrence of the trapezoidal rule on the
  probe, equals the discrete formula tan(w_h h/2) = w_s h/2, w_s^2 = 4 s^2 / (dx^2 (1 - 2 alpha s^2/3))
  to 1e-9 (the mass assembled as given), for alpha = 1/2 and tuned, at 10, 20, 40 elements;
- at c h/dx = 0.5 its error against the exact pi is second order in dx with MIXED (ratio 4 per
  halving, 3.5 to 4.5) and fourth order tuned (ratio 16, 14 to 18), tuned 50 times smaller at 10
  elements;
- TUNED takes alpha = 3/4 at c h/dx = 0.5: the same frequency as MIXED 0.75 (1e-9);
- MASS MIXED and MASS MIXED 0.5 give the same bits.
Impact (code_aster SDNV100's bar, ../contact_massless/sdnv100_bar.dat, 20 elements):
- at h = dx/c (the benchmark's own step, 2e-6 s), TUNED (alpha 1.4999) under AUTO, which takes
  PERSIST there (stdout): the uniform lattice is then exact; rebound within 0.01 % of 100 m/s,
  release at 2L/c to the step, force std/mean <= 1 %, mean within 0.1 % of rho c v0 A, one onset,
  |balance| <= 1e-10 of E; MIXED 1.4999 with IMPACT PERSIST gives the same bits;
- at h = dx/(2c), TUNED (alpha = 3/4) under AUTO (SYMMETRIC): rebound within 0.5 %, at most a third
  of MIXED's error (-1.38 %), release within one step of 2L/c.
The default mass (docs/contact.md, "The default mass"; inputs/sdnv100.dat, the benchmark at its own
settings with no MASS and no SCHEME IMPACT):
- as given (h = dx/c): stdout says the mass is tuned and AUTO takes PERSIST, and every target of the
  TUNED run above holds; the same bits as MASS TUNED;
- at c h/dx = 0.1: rebound within 0.5 % at 20 elements, and its error falls at 80 and at 320;
- at h = 1.1 dx/c, where no tuned mass exists, on a KINEMATICS LARGE model, and on an ELASTOPLASTIC
  bar: the consistent mass (the same bits as MASS CONSISTENT; AUTO takes MASSLESS, PERSIST,
  PERSIST: a nonlinear law at a contact node, docs/contact.md), and stdout says nothing of a tuned mass.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

MODAL = os.path.join('tests', 'scenes', 'tuned_mass', 'modal_bar.dat')
BAR = os.path.join('tests', 'scenes', 'contact_massless', 'sdnv100_bar.dat')
DEFAULT = os.path.join('inputs', 'sdnv100.dat')


def discrete_w(n, r, alpha):
    dx, s = 1.0 / n, np.sin(np.pi / n / 2)
    ws = np.sqrt(4 * s * s / (dx * dx * (1 - 2 * alpha * s * s / 3)))
    return 2 / (r * dx) * np.arctan(ws * r * dx / 2)


def measured_w(out, h):
    u = sc.probes(out)['bar.mid.UX']
    # u(n+1) + u(n-1) = 2 cos(w_h h) u(n), in the least-squares sense over every step.
    cosw = np.dot(u[1:-1], u[2:] + u[:-2]) / (2 * np.dot(u[1:-1], u[1:-1]))
    return np.arccos(cosw) / h


R = 0.5
errs = {}
for label, alpha in (('MIXED', 0.5), ('tuned', 0.5 + R * R)):
    errs[label] = []
    for n in (10, 20, 40):
        h = R / n
        out = sc.run_ok(MODAL, ['LINE.bar.ELEMENTS=%d' % n, 'TIME.STEP=%r' % h, 'MODEL.bar.MASS=MIXED %r' % alpha])
        w = measured_w(out, h)
        sc.close('%s (alpha %g), %d elements: frequency = the discrete formula' % (label, alpha, n), w,
                 discrete_w(n, R, alpha), 1e-9)
        errs[label].append(w / np.pi - 1)
for label, lo, hi in (('MIXED', 3.5, 4.5), ('tuned', 14.0, 18.0)):
    e = errs[label]
    ratios = [e[0] / e[1], e[1] / e[2]]
    sc.report_measured('%s at c h/dx = 0.5: phase error ratio per halving of dx in [%g, %g]' % (label, lo, hi),
                       all(lo <= q <= hi for q in ratios),
                       'errors %s, ratios %s' % (', '.join('%.3e' % x for x in e), ', '.join('%.2f' % q for q in ratios)))
sc.report_measured('tuned: phase error at 10 elements 50 times smaller than MIXED',
                   abs(errs['tuned'][0]) * 50 <= abs(errs['MIXED'][0]),
                   '%.3e vs %.3e' % (errs['tuned'][0], errs['MIXED'][0]))
for n in (10, 20, 40):
    out = sc.run_ok(MODAL, ['LINE.bar.ELEMENTS=%d' % n, 'TIME.STEP=%r' % (R / n), 'MODEL.bar.MASS=TUNED'])
    sc.close('TUNED at c h/dx = 0.5, %d elements: the frequency of alpha = 3/4' % n, measured_w(out, R / n),
             discrete_w(n, R, 0.5 + R * R), 1e-9)
a = sc.probes(sc.run_ok(MODAL, ['MODEL.bar.MASS=MIXED']))['bar.mid.UX']
b = sc.probes(sc.run_ok(MODAL, ['MODEL.bar.MASS=MIXED 0.5']))['bar.mid.UX']
sc.report('MASS MIXED and MASS MIXED 0.5: the same bits', np.array_equal(a, b))

# SDNV100's bar: L 0.2 m, 20 elements, c = 5000 m/s, dx/c = 2e-6 s; exact release at 2L/c = 8e-5 s
# after the contact at 2e-5 s, force rho c v0 A.
M, V0, F, DXC = 8000 * 4e-4 * 0.2, 100.0, 1.6e6, 2e-6


def impact(tag, sets, h, reb_tol, force_checks, auto=None, scene=BAR):
    out = sc.new_dir('impact')
    r = sc.run_limited([sc.REBOND, scene, '-o', out, '--set', 'TIME.STEP=%r' % h] + sum((['--set', x] for x in sets), []),
                       120, cwd=sc.ROOT, capture_output=True, text=True)
    if auto:
        sc.report(tag + ': AUTO takes ' + auto, r.returncode == 0 and 'IMPACT %s (AUTO)' % auto in r.stdout)
    if scene == DEFAULT:
        sc.report(tag + ': stdout says the mass is tuned to the step', 'bar: mass tuned to the step' in r.stdout)
    hist, c = sc.history(out), sc.contacts(out)
    cc.check_balance(tag, out)
    err = hist['momentum_x'][-1] / M / V0 - 1
    sc.report_measured(tag + ': rebound within %g %% of 100 m/s' % (100 * reb_tol), abs(err) <= reb_tol,
                       '%+.4f %%' % (100 * err))
    on = np.nonzero(c['force_x'] > 0)[0]
    rel = (c['time'][on[-1]] - 1e-4) / h
    sc.report_measured(tag + ': release within one step of 2L/c', abs(rel) <= 1 + 1e-6, '%+.2f steps' % rel)
    onsets = sum(1 for e in cc.events(out) if e[3] == 'establish')
    sc.report(tag + ': one contact onset', onsets == 1, '%d onsets' % onsets)
    if force_checks:
        f = c['force_x'][on[0]:on[-1] + 1]
        f = f[len(f) // 10:9 * len(f) // 10]
        sc.report_measured(tag + ': force std/mean <= 1 %, mean within 0.1 % of rho c v0 A',
                           f.std() / f.mean() <= 0.01 and abs(f.mean() / F - 1) <= 1e-3,
                           'std/mean %.4f, mean %+.3f %%' % (f.std() / f.mean(), 100 * (f.mean() / F - 1)))
    return err


exact = impact('h = dx/c, TUNED, AUTO', ['MODEL.bar.MASS=TUNED', 'SCHEME.IMPACT=AUTO'], DXC, 1e-4, True, 'PERSIST')
out = sc.run_ok(BAR, ['TIME.STEP=%r' % DXC, 'MODEL.bar.MASS=MIXED 1.4999', 'SCHEME.IMPACT=PERSIST'])
sc.report('h = dx/c: MIXED 1.4999 with PERSIST, the same bits as TUNED under AUTO',
          sc.history(out)['momentum_x'][-1] / M / V0 - 1 == exact)
tuned = impact('h = dx/(2c), TUNED, AUTO', ['MODEL.bar.MASS=TUNED', 'SCHEME.IMPACT=AUTO'], DXC / 2, 5e-3, True,
               'SYMMETRIC')
out = sc.run_ok(BAR, ['TIME.STEP=%r' % (DXC / 2), 'MODEL.bar.MASS=MIXED', 'SCHEME.IMPACT=AUTO'])
mixed = sc.history(out)['momentum_x'][-1] / M / V0 - 1
sc.report_measured('h = dx/(2c): the tuned rebound error at most a third of MIXED\'s', abs(tuned) * 3 <= abs(mixed),
                   'tuned %+.3f %%, MIXED %+.3f %%' % (100 * tuned, 100 * mixed))

# The default mass: inputs/sdnv100.dat says no MASS and no IMPACT.
dflt = impact('SDNV100 as given (default mass, h = dx/c)', [], DXC, 1e-4, True, 'PERSIST', DEFAULT)
out = sc.run_ok(DEFAULT, ['MODEL.bar.MASS=TUNED'])
sc.report('SDNV100 as given: the same bits as MASS TUNED', sc.history(out)['momentum_x'][-1] / M / V0 - 1 == dflt)
errs = []
for n in (20, 80, 320):
    out = sc.run_ok(DEFAULT, ['LINE.bar.ELEMENTS=%d' % n, 'TIME.STEP=%r' % (0.1 * DXC * 20 / n), 'OUTPUT.FIELDS=EVERY 0'])
    errs.append(sc.history(out)['momentum_x'][-1] / M / V0 - 1)
sc.report_measured('default mass at c h/dx = 0.1: rebound within 0.5 % at 20 elements, falling at 80 and 320',
                   abs(errs[0]) <= 5e-3 and abs(errs[0]) > abs(errs[1]) > abs(errs[2]),
                   ', '.join('%+.3f %%' % (100 * e) for e in errs))
with open(os.path.join(sc.ROOT, DEFAULT)) as f:
    PLASTIC = sc.write_scene('plastic_default.dat', f.read().replace(
        'steel ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000', 'steel ELASTOPLASTIC YOUNG 2e11 YIELD 2.5e8 H_ISO 2e10 DENSITY 8000'))
for tag, scene, sets, auto in (('h = 1.1 dx/c', DEFAULT, ['TIME.STEP=%r' % (1.1 * DXC)], 'MASSLESS'),
                               ('KINEMATICS LARGE', DEFAULT, ['MODEL.bar.KINEMATICS=LARGE'], 'PERSIST'),
                               ('ELASTOPLASTIC', PLASTIC, [], 'PERSIST')):
    out = sc.new_dir('default')
    r = sc.run_limited([sc.REBOND, scene, '-o', out] + sum((['--set', x] for x in sets), []), 120, cwd=sc.ROOT,
                       capture_output=True, text=True)
    ref = sc.run_ok(scene, sets + ['MODEL.bar.MASS=CONSISTENT'])
    sc.report('default mass, %s: consistent (the same bits as MASS CONSISTENT), AUTO takes %s, no tuned mass said'
              % (tag, auto), r.returncode == 0 and 'IMPACT %s (AUTO)' % auto in r.stdout and 'tuned' not in r.stdout
              and np.array_equal(sc.history(out)['momentum_x'], sc.history(ref)['momentum_x']))
