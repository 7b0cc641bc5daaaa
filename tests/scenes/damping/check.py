"""Rayleigh damping (issue 13, item 5): MODEL … DAMPING ALPHA a BETA b, C = a M + b K0.

The scheme with damping is eq (9) with 2C du/h on the left (docs/input.md, "Damping"): the
trapezoid rule's ½C(v(n) + v(n+1)) = C du/h. It removes exactly du'C du/h per step, which
history.csv books in the column `damping`, so the balance stays at round-off.

- the oscillator of tests/scenes/sdof_period (m = 2, k = 8, ω = 2) with ζ = 0.1 by ALPHA 0.4
  on the mass, and with ζ = 0.1 by BETA 0.1 on the spring: the motion converges to the exact
  damped one u0 e^{-ζωt}(cos ω_d t + ζ/√(1-ζ²) sin ω_d t) at second order in h;
- the damping column is Σ a m du²/h computed from the probes (the booking is the scheme's);
- |balance| <= 1e-12 of the initial energy at every step, damped energy decreasing;
- the inclined beam drop (PERSIST) with BETA 1e-4 settles on the ground (all 21 nodes in contact,
  kinetic energy < 1e-12 of the released energy, no contact event after 0.5 s; undamped it still
  bounces), balance <= 1e-10;
- the J2 block (plasticity, eq (9)'s correction) with BETA 1e-5: balance <= 1e-10;
- DAMPING ALPHA -1, DAMPING GAMMA 1, DAMPING with SCHEME PRECISION EXTENDED: exit 2.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

SDOF = os.path.join(sc.ROOT, 'tests/scenes/sdof_period/sdof.dat')
M, K, U0 = 2.0, 8.0, 0.1
W = math.sqrt(K / M)


def scene(tag, old, new):
    text = open(SDOF).read()
    assert old in text
    return sc.write_scene(tag + '.dat', text.replace(old, new))


ALPHA = scene('alpha', 'MODEL     point  SECTION pm', 'MODEL     point  SECTION pm DAMPING ALPHA 0.4')
BETA = scene('beta', 'MODEL     spring MATERIAL k', 'MODEL     spring MATERIAL k DAMPING BETA 0.1')


def exact(t, zeta):
    wd = W * math.sqrt(1 - zeta ** 2)
    return U0 * np.exp(-zeta * W * t) * (np.cos(wd * t) + zeta / math.sqrt(1 - zeta ** 2) * np.sin(wd * t))


def run(path, h):
    out = sc.run_ok(path, ['TIME.STEP=%r' % h, 'TIME.END=10'])
    return sc.read_csv(os.path.join(out, 'probes.csv')), sc.read_csv(os.path.join(out, 'history.csv'))


def convergence(tag, path, zeta):
    errs = []
    for h in (0.02, 0.01, 0.005):
        p, hist = run(path, h)
        errs.append(np.max(np.abs(p['tip.UX'] - exact(p['time'], zeta))) / U0)
    r1, r2 = errs[0] / errs[1], errs[1] / errs[2]
    sc.report('%s: converges to the exact damped motion at order 2 (errors %.2e %.2e %.2e, ratios %.2f %.2f)'
              % (tag, errs[0], errs[1], errs[2], r1, r2), 3.8 < r1 < 4.2 and 3.8 < r2 < 4.2 and errs[2] < 1e-4,
              'errors %s' % errs)


def energy(tag, path, alpha=None):
    p, hist = run(path, 0.01)
    e0 = hist['kinetic'][0] + hist['internal'][0]
    bal = np.max(np.abs(hist['balance'])) / e0
    sc.report('%s: |balance| <= 1e-12 of the initial energy with the damping booked (%.1e)' % (tag, bal), bal <= 1e-12,
              '%.3e' % bal)
    mech = hist['kinetic'] + hist['internal']
    sc.report('%s: the mechanical energy decreases, the damping column grows' % tag,
              np.all(np.diff(mech) <= 1e-15 * e0) and np.all(np.diff(hist['damping']) >= 0) and
              hist['damping'][-1] > 0.9 * e0, 'final damping %.4g of %.4g' % (hist['damping'][-1], e0))
    if alpha is not None:
        du = np.diff(p['tip.UX'])
        book = np.cumsum(alpha * M * du ** 2 / 0.01)
        rel = np.max(np.abs(book - hist['damping'][1:])) / e0
        sc.report('%s: damping = Σ a m du²/h from the probes (%.1e)' % (tag, rel), rel <= 1e-13, '%.3e' % rel)


def beam():
    """The inclined beam drop (PERSIST): undamped it keeps bouncing; with BETA 1e-4 (stiffness
    damping of the high modes) it settles on the ground with its 21 nodes in contact."""
    base = ['TIME.STEP=1e-4', 'TIME.END=1.2', 'SCHEME.IMPACT=PERSIST']
    runs = {}
    for tag, extra in (('undamped', []), ('damped', ['MODEL.beam.DAMPING=BETA 1e-4'])):
        out = sc.run_ok('inputs/beam_drop_inclined.dat', base + extra)
        h = sc.read_csv(os.path.join(out, 'history.csv'))
        late = sum(1 for ln in open(os.path.join(out, 'events.csv')).readlines()[1:] if float(ln.split(',')[1]) > 0.5)
        runs[tag] = (h, late)
    h, late = runs['damped']
    work = np.max(h['external'])   # the potential energy gravity released
    bal = np.max(np.abs(h['balance'])) / work
    sc.report('damped inclined beam drop: |balance| <= 1e-10 of the work of gravity (%.1e), damping %.3g J'
              % (bal, h['damping'][-1]), bal <= 1e-10 and h['damping'][-1] > 0.5 * work, '%.3e' % bal)
    ke = h['kinetic'][-1] / work
    sc.report('damped beam settles: kinetic %.1e of the released energy at 1.2 s, 21 nodes in contact, no contact '
              'event after 0.5 s' % ke, ke < 1e-12 and h['active_contacts'][-1] == 21 and late == 0,
              'ke %.3e, active %d, late events %d' % (ke, h['active_contacts'][-1], late))
    h0, late0 = runs['undamped']
    sc.report('undamped, it still bounces (kinetic %.2f of the released energy, %d events after 0.5 s)'
              % (h0['kinetic'][-1] / work, late0), h0['kinetic'][-1] > 0.1 * work and late0 > 100, '')


def plastic():
    """Damping with a nonlinear law (the J2 block: eq (9)'s correction and plasticity)."""
    out = sc.run_ok('inputs/block_j2.dat', ['MODEL.block.DAMPING=BETA 1e-5'])
    h = sc.read_csv(os.path.join(out, 'history.csv'))
    work = np.max(np.abs(h['external']))
    bal = np.max(np.abs(h['balance'])) / work
    sc.report('damped J2 block: |balance| <= 1e-10 of the external work (%.1e), plastic work %.3g J, damping %.3g J'
              % (bal, h['dissipated'][-1], h['damping'][-1]),
              bal <= 1e-10 and h['dissipated'][-1] > 0 and h['damping'][-1] > 0, '%.3e' % bal)


def refused():
    for tag, new in (('ALPHA -1', 'DAMPING ALPHA -1'), ('GAMMA 1', 'DAMPING GAMMA 1'), ('odd count', 'DAMPING ALPHA')):
        path = scene('bad_' + tag.replace(' ', '_'), 'MODEL     point  SECTION pm', 'MODEL     point  SECTION pm ' + new)
        line = 1 + open(path).read().split('\n').index(next(ln for ln in open(path).read().split('\n')
                                                               if ln.startswith('MODEL     point')))
        rc, err, out = sc.run(path, outdir=sc.new_dir('never'))
        sc.report('DAMPING %s refused: exit 2, MODEL named' % tag, rc == 2 and ('%s:%d: MODEL point' % (path, line)) in err and
                  not os.path.exists(out), 'exit %d: %r' % (rc, err))
    rc, err, out = sc.run(ALPHA, ['SCHEME.PRECISION=EXTENDED'], outdir=sc.new_dir('never'))
    sc.report('DAMPING with PRECISION EXTENDED refused', rc == 2 and 'DAMPING' in err, 'exit %d: %r' % (rc, err))


convergence('ALPHA 0.4 on the mass (ζ = 0.1)', ALPHA, 0.1)
convergence('BETA 0.1 on the spring (ζ = 0.1)', BETA, 0.1)
energy('ALPHA', ALPHA, alpha=0.4)
energy('BETA', BETA)
beam()
plastic()
refused()
