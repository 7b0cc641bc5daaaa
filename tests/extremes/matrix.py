#!/usr/bin/python3
"""Stability at the extremes (issue 5, deliverable 4): the matrix of cases and its runner.

    /usr/bin/python3 tests/extremes/matrix.py [--fast] [--only KEY,...] [--out DIR]
                                              [--markdown FILE] [--jobs N] [--list]

Every case runs bin/rebond on a scene of tests/scenes/extremes/ (or inputs/) with --set
overrides and must end in one of two ways:

- `ok`: exit 0, every number of history.csv, probes.csv, events.csv and fields.h5 finite, and
  max |balance| / max(kinetic + internal) (history.csv) within the case's stated bound; plus
  the case's physics checks (exact solutions where they exist);
- `refuse`: the expected exit status (2 bad input, 1 failure during the run) with a message
  naming the cause (a given substring of stderr); an input refusal writes nothing.

Anything else (a crash, a NaN, a bound exceeded, a hang past the timeout, an unexpected
success or refusal) is a FAIL. One line `PASS name` / `FAIL name: detail` per assertion, as
tests/scenes/*/check.py print them; tests/scenes/extremes/check.py runs the `fast` subset
(`make test`), `make extremes` all of it (table in results/extremes/matrix.md, copied into
docs/extremes.md).
"""
import argparse
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'scenes'))
from scenecheck import run_limited  # noqa: E402
REBOND = os.environ.get('REBOND', os.path.join(ROOT, 'bin', 'rebond'))
SC = 'tests/scenes/extremes/'

# Scene constants used by the exact checks (they restate the scene files' headers).
OSC_M, OSC_K, OSC_U0 = 2.0, 8.0, 0.1            # oscillator.dat
OSC_W = math.sqrt(OSC_K / OSC_M)
OSC_T = 2.0 * math.pi / OSC_W                    # pi s
G = 9.81
CANT_T1 = 0.1193                                 # cantilever_release.dat first period (s)


class Case:
    def __init__(self, key, group, what, scene, sets=(), expect='ok', bound=None, fast=False,
                 checks=(), timeout=300, code=None, message=None, note='', defect=None):
        self.key, self.group, self.what, self.scene = key, group, what, scene
        self.sets = list(sets)
        self.expect, self.bound, self.fast = expect, bound, fast
        self.checks, self.timeout = list(checks), timeout
        self.code, self.message, self.note = code, message, note
        self.defect = defect          # a src/ defect this case exposes (docs/extremes.md); never in --fast


# ----------------------------------------------------------------------------------------------
# Reading the outputs
# ----------------------------------------------------------------------------------------------

def read_csv(path, text_cols=()):
    """Columns of a rebond CSV as name -> float array, and the count of non-finite or
    unreadable numeric fields (a Fortran '*****' overflow counts as unreadable)."""
    with open(path) as f:
        names = f.readline().strip().split(',')
        rows = [line.strip().split(',') for line in f if line.strip()]
    bad = 0
    cols = {n: [] for n in names}
    for r in rows:
        for i, n in enumerate(names):
            v = r[i] if i < len(r) else ''
            if n in text_cols:
                cols[n].append(v)
                continue
            try:
                x = float(v)
            except ValueError:
                x = float('nan')
            if not math.isfinite(x):
                bad += 1
            cols[n].append(x)
    out = {}
    for n in names:
        out[n] = np.array(cols[n], dtype=object if n in text_cols else float)
    return out, bad


def nonfinite_fields(outdir):
    """Number of non-finite values in the float datasets of fields.h5 (0 when absent)."""
    path = os.path.join(outdir, 'fields.h5')
    if not os.path.exists(path):
        return 0
    try:
        import h5py
    except ImportError:
        return 0
    bad = [0]

    def visit(_name, obj):
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind == 'f':
            bad[0] += int(np.size(obj[()]) - np.count_nonzero(np.isfinite(obj[()])))
    with h5py.File(path, 'r') as f:
        f.visititems(visit)
    return bad[0]


class Out:
    """The outputs of one run."""

    def __init__(self, outdir):
        self.dir = outdir
        self.bad = 0
        self.hist = self.probes = self.events = None
        p = os.path.join(outdir, 'history.csv')
        if os.path.exists(p):
            self.hist, b = read_csv(p)
            self.bad += b
        p = os.path.join(outdir, 'probes.csv')
        if os.path.exists(p):
            self.probes, b = read_csv(p)
            self.bad += b
        p = os.path.join(outdir, 'events.csv')
        if os.path.exists(p):
            self.events, b = read_csv(p, text_cols=('event', 'nodes', 'contact'))
            self.bad += b
        self.bad += nonfinite_fields(outdir)

    def rel_balance(self):
        h = self.hist
        scale = np.max(np.abs(h['kinetic'] + h['internal']))
        return float(np.max(np.abs(h['balance'])) / scale) if scale > 0 else float('nan')

    def establish_times(self):
        if self.events is None or len(self.events['step']) == 0:
            return np.array([]), np.array([])
        m = self.events['event'] == 'establish'
        return self.events['step'][m].astype(float), self.events['time'][m].astype(float)


# ----------------------------------------------------------------------------------------------
# Physics checks: each returns (name, ok, detail)
# ----------------------------------------------------------------------------------------------

def osc_exact(h, tol):
    """u_n = u0 cos(Omega n h), Omega h = 2 atan(omega h / 2): the trapezoidal rule's exact
    discrete solution; max |u - exact| <= tol u0."""
    def check(o):
        n = o.probes['step']
        u = o.probes['tip.UX']
        wh = 2.0 * math.atan(OSC_W * h / 2.0)
        err = float(np.max(np.abs(u - OSC_U0 * np.cos(wh * n)))) / OSC_U0
        return ('u = u0 cos(Omega n h)', err <= tol, 'max |u - exact| / u0 = %.2e (bound %.0e)' % (err, tol))
    return check


def ball_final_velocity(vx, vy, tol):
    """Velocity over the last step (probe displacements) equals (vx, vy) within tol (m/s)."""
    def check(o):
        t = o.probes['time']
        ux, uy = o.probes['ball.UX'], o.probes['ball.UY']
        dt = t[-1] - t[-2]
        wx, wy = (ux[-1] - ux[-2]) / dt, (uy[-1] - uy[-2]) / dt
        err = max(abs(wx - vx), abs(wy - vy))
        return ('final velocity (%g, %g)' % (vx, vy), err <= tol,
                'measured (%.15g, %.15g), |error| %.2e (bound %.0e)' % (wx, wy, err, tol))
    return check


def ball_no_penetration(y0, tol):
    def check(o):
        g = float(np.min(y0 + o.probes['ball.UY']))
        return ('gap >= -%g' % tol, g >= -tol, 'min gap %.3e m' % g)
    return check


def ball_stays(y0, tol):
    """Grazing / resting: the normal position stays y0 within tol."""
    def check(o):
        d = float(np.max(np.abs(o.probes['ball.UY'])))
        return ('normal displacement stays 0', d <= tol, 'max |UY| = %.3e m (bound %.0e)' % (d, tol))
    return check


def count_events(kind, lo, hi):
    def check(o):
        n = 0 if o.events is None else int(np.sum(o.events['event'] == kind))
        return ('%d <= %s events <= %d' % (lo, kind, hi), lo <= n <= hi, '%d %s events' % (n, kind))
    return check


def first_establish(t_exact, h):
    """The first contact establishment falls in the step containing the exact time."""
    def check(o):
        _, t = o.establish_times()
        if len(t) == 0:
            return ('first contact at %.6g s' % t_exact, False, 'no establish event')
        ok = t[0] - h - 1e-12 <= t_exact <= t[0] + 1e-12
        return ('first contact in the step of t = %.6g s' % t_exact, ok,
                'establish at step end %.9g s, h = %g' % (t[0], h))
    return check


def simultaneous(n_expected):
    """n_expected conditions established in one and the same step."""
    def check(o):
        s, _ = o.establish_times()
        if len(s) == 0:
            return ('%d simultaneous impacts' % n_expected, False, 'no establish event')
        vals, counts = np.unique(s, return_counts=True)
        return ('%d simultaneous impacts' % n_expected, int(counts.max()) == n_expected,
                'largest number established in one step: %d (step %d)' % (counts.max(), vals[np.argmax(counts)]))
    return check


def two_masses_exact(mb, tol):
    """Elastic collision of ma = 1 kg at 1 m/s with mb at rest."""
    def check(o):
        t = o.probes['time']
        dt = t[-1] - t[-2]
        va = (o.probes['a.UX'][-1] - o.probes['a.UX'][-2]) / dt
        vb = (o.probes['b.UX'][-1] - o.probes['b.UX'][-2]) / dt
        ea, eb = (1.0 - mb) / (1.0 + mb), 2.0 / (1.0 + mb)
        err = max(abs(va - ea), abs(vb - eb))
        return ('elastic collision velocities', err <= tol,
                'va %.15g (exact %.15g), vb %.15g (exact %.15g), max error %.2e (bound %.0e)'
                % (va, ea, vb, eb, err, tol))
    return check


def plastic_path_energy(m, v0, fy, ey, length, tol):
    """One monotone step of a perfectly plastic member carrying mass m: the exact work along
    the computed path, W = Fy (e - ey/2) L (e = u/L the strain, beyond yield), plus the kinetic
    energy must equal the initial kinetic energy: |T + W - T0| <= tol T0. This sees the
    sub-increment error that `balance` (built from the same sub-increments) cannot."""
    def check(o):
        h = o.hist
        u = o.probes['tip.UX'][-1]
        e = u / length
        w = fy * (e - ey / 2.0) * length if e > ey else 0.5 * fy / ey * e * e * length
        t0 = 0.5 * m * v0 * v0
        err = abs(h['kinetic'][-1] + w - t0) / t0
        wn = h['internal'][-1]
        return ('exact path energy |T + W_exact - T0| / T0', err <= tol,
                '%.2e (bound %.0e); W_N (history) %.8g J vs W_exact %.8g J (relative %.2e)'
                % (err, tol, wn, w, abs(wn - w) / w))
    return check


def bounce_period(t_first, period, h, t_end):
    """Endless bouncing of the point mass: every interval between contact establishments is
    the exact bounce period within one step (the step quantizes each impact), the first impact
    falls in the step of the exact time, and impacts go on to the end of the run."""
    def check(o):
        _, t = o.establish_times()
        if len(t) < 2:
            return ('bounce period', False, '%d impacts' % len(t))
        d = np.diff(t)
        ok = (abs(t[0] - t_first) <= h and np.all(np.abs(d - period) <= h + 1e-9)
              and t[-1] >= t_end - period - h)
        return ('bounce period = 2 sqrt(2H/g) within h, to the end', bool(ok),
                '%d impacts, first at %.6g s (exact %.6g), intervals %.9g ... %.9g s (exact %.9g, h = %g), '
                'last at %.6g s' % (len(t), t[0], t_first, d.min(), d.max(), period, h, t[-1]))
    return check


def total_steps(n):
    def check(o):
        last = int(o.hist['step'][-1])
        return ('%d steps' % n, last == n, 'last step %d' % last)
    return check


# ----------------------------------------------------------------------------------------------
# The matrix
# ----------------------------------------------------------------------------------------------

def _g(x):
    return repr(float(x))


def build_cases():
    c = []
    osc = SC + 'oscillator.dat'
    # 1. Time step, 1e-8 s ... 10 x the slowest period, 1000 steps each (oscillator T = pi s).
    for h, fast in [(1e-8, True), (1e-6, False), (1e-4, False), (1e-2, False), (0.1, False),
                    (OSC_T, False), (10 * OSC_T, True)]:
        lab = '10T' if h == 10 * OSC_T else ('T' if h == OSC_T else '%g' % h)
        c.append(Case('step_osc_h%s' % lab, 'step', 'oscillator (T = pi s), h = %s, 1000 steps' % lab, osc,
                      ['TIME.STEP=' + _g(h), 'TIME.END=' + _g(1000 * h)], bound=1e-12, fast=fast,
                      checks=[osc_exact(h, 1e-9), total_steps(1000)]))
    cant = 'inputs/cantilever_release.dat'
    for h, lab, bound, prec, fast in [(1e-8, '1e-8', 1e-12, 'DOUBLE', True),
                                      (10 * CANT_T1, '10T1', 1e-6, 'DOUBLE', False),
                                      (10 * CANT_T1, '10T1', 1e-12, 'EXTENDED', True)]:
        c.append(Case('step_cantilever_h%s_%s' % (lab, prec.lower()), 'step',
                      'cantilever (20 BEAM2, T1 = 0.1193 s), h = %s, 1000 steps, %s' % (lab, prec), cant,
                      ['TIME.STEP=' + _g(h), 'TIME.END=' + _g(1000 * h), 'OUTPUT.FIELDS=0',
                       'SCHEME.PRECISION=' + prec], bound=bound, fast=fast, checks=[total_steps(1000)]))
    ball = SC + 'ball.dat'
    # contact with a tiny step: gap 1e-6 m at 1 m/s, impact after 100 steps
    c.append(Case('step_ball_h1e-8', 'step', 'point mass hits the ground, h = 1e-8 s (impact at step 100)', ball,
                  ['NODE.ball.AT=0 1e-6', 'TIME.STEP=1e-8', 'TIME.END=3e-6'], bound=1e-11, fast=True,
                  checks=[ball_final_velocity(0, 1, 1e-6), ball_no_penetration(1e-6, 1e-15),
                          count_events('establish', 1, 1)]))
    # contact with a huge step: the 1 m drop (bounce period 2 sqrt(2/g) = 0.903 s), h = 10 periods
    tb = 2 * math.sqrt(2 / G)
    c.append(Case('step_ball_h10T', 'step', 'point mass dropped from 1 m under gravity, h = 10 bounce periods',
                  ball, ['NODE.ball.AT=0 1', 'INITIAL.ball.VELOCITY=0 0', 'GRAVITY.GY=-9.81',
                         'TIME.STEP=' + _g(10 * tb), 'TIME.END=' + _g(100 * tb)], bound=1e-12, fast=True,
                  checks=[ball_no_penetration(1.0, 1e-12)]))
    vdrop = 'inputs/beam_drop_vertical.dat'
    # vertical beam drop: 1e-8 s from a 1e-8 m drop (impact at step ~4500), and 10 x its slowest
    # vibration period (first free-free bending mode, 53 Hz: T = 0.0189 s)
    c.append(Case('step_beamdrop_h1e-8', 'step', 'vertical beam, 1e-8 m drop, h = 1e-8 s, 10000 steps', vdrop,
                  ['LINE.beam.FROM=0 1e-8', 'LINE.beam.TO=0 1.00000001', 'TIME.STEP=1e-8', 'TIME.END=1e-4',
                   'OUTPUT.FIELDS=0', 'OUTPUT.HISTORY=1'], bound=1e-10, fast=False, defect='D1',
                  checks=[first_establish(math.sqrt(2 * 1e-8 / G), 1e-8)]))
    for prec, bound in [('DOUBLE', 1e-8), ('EXTENDED', 1e-12)]:
        c.append(Case('step_beamdrop_h10T_%s' % prec.lower(), 'step',
                      'vertical beam drop (2 cm), h = 10 x 0.0189 s (slowest mode), 20 steps, %s' % prec,
                      vdrop, ['TIME.STEP=0.189', 'TIME.END=3.78', 'OUTPUT.FIELDS=0', 'OUTPUT.HISTORY=1',
                              'SCHEME.PRECISION=' + prec], bound=bound, fast=True,
                      checks=[first_establish(math.sqrt(2 * 0.02 / G), 0.189)],
                      note='DOUBLE: round-off of S = K0 + 4M/h^2 (condition ~ (omega_max h)^2), docs/precision.md'
                      if prec == 'DOUBLE' else ''))

    # 2. Young's modulus over 12 decades, same scene (vertical beam drop, h = 1e-5 s, 0.1 s).
    for k in range(0, 13):
        e = 10.0 ** k
        c.append(Case('young_1e%d' % k, 'young', 'vertical beam drop, E = 1e%d Pa' % k, vdrop,
                      ['MATERIAL.steel.YOUNG=%g' % e, 'TIME.END=0.1', 'OUTPUT.FIELDS=0'], bound=1e-10,
                      fast=k in (0, 6, 12), checks=[first_establish(math.sqrt(2 * 0.02 / G), 1e-5)]))

    # 3. Mass ratios 1e-6 ... 1e6.
    for k in range(-6, 7, 2):
        r = 10.0 ** k
        c.append(Case('mass_bar_1e%d' % k, 'mass', 'bar (0.78 kg) + end mass %g x the bar, hits a wall' % r,
                      SC + 'bar_mass.dat', ['SECTION.tipm.MASS=%r' % (0.78 * r)], bound=1e-10,
                      fast=k in (-6, 6), checks=[count_events('establish', 1, 10 ** 6)]))
    for k in range(-6, 7, 3):
        r = 10.0 ** k
        c.append(Case('mass_pair_1e%d' % k, 'mass', 'two point masses colliding, mb/ma = %g' % r,
                      SC + 'two_masses.dat', ['SECTION.mb.MASS=%r' % r], bound=1e-12, fast=k in (-6, 6),
                      checks=[two_masses_exact(r, 1e-10)]))

    # 4. Tiny gaps and contact at t = 0.
    c.append(Case('gap_1e-12', 'gap', 'point mass 1e-12 m above the ground at 1 m/s', ball,
                  ['NODE.ball.AT=0 1e-12'], bound=1e-12, fast=True,
                  checks=[ball_final_velocity(0, 1, 1e-9), ball_no_penetration(1e-12, 1e-15),
                          count_events('establish', 1, 1)]))
    c.append(Case('gap_0_approaching', 'gap', 'contact at t = 0, moving into the ground at 1 m/s', ball,
                  ['NODE.ball.AT=0 0'], bound=1e-12, fast=True,
                  checks=[ball_final_velocity(0, 1, 1e-9), ball_no_penetration(0, 1e-15)]))
    c.append(Case('gap_0_leaving', 'gap', 'contact at t = 0, leaving at 1 m/s', ball,
                  ['NODE.ball.AT=0 0', 'INITIAL.ball.VELOCITY=0 1'], bound=1e-12, fast=True,
                  checks=[ball_final_velocity(0, 1, 1e-9), count_events('establish', 0, 0)]))
    c.append(Case('gap_0_resting', 'gap', 'contact at t = 0, at rest under gravity', ball,
                  ['NODE.ball.AT=0 0', 'INITIAL.ball.VELOCITY=0 0', 'GRAVITY.GY=-9.81', 'TIME.END=1'],
                  bound=None, fast=True, checks=[ball_stays(0, 1e-12)],
                  note='no motion: kinetic + internal is 0, the balance is checked absolute (== 0)'))
    c.append(Case('gap_penetration', 'gap', 'starts 1e-3 m inside the ground', ball, ['NODE.ball.AT=0 -1e-3'],
                  expect='refuse', code=2, message='inside the obstacle', fast=True))
    flat = 'inputs/beam_land_flat.dat'
    fb = SC + 'flat_beam.dat'
    c.append(Case('gap_beam_1e-12', 'gap', 'flat beam (21 nodes) 1e-12 m above the ground, under gravity', fb,
                  ['LINE.beam.FROM=0 1e-12', 'LINE.beam.TO=1 1e-12'], bound=1e-10, fast=True,
                  checks=[simultaneous(21)]))
    c.append(Case('gap_beam_0_falling', 'gap', 'flat beam on the ground at t = 0, moving down at 1 m/s', fb,
                  ['LINE.beam.FROM=0 0', 'LINE.beam.TO=1 0', 'INITIAL.beam.VELOCITY=0 -1'], bound=1e-10, fast=True,
                  checks=[simultaneous(21)]))
    c.append(Case('gap_beam_0_resting', 'gap', 'flat beam resting on the ground at t = 0, under gravity', fb,
                  ['LINE.beam.FROM=0 0', 'LINE.beam.TO=1 0'], bound=1e-10, fast=True))
    c.append(Case('gap_beam_-5e-11_falling', 'gap',
                  'flat beam 5e-11 m inside the ground (accepted: < 1e-10 x size), moving down at 1 m/s', fb,
                  ['LINE.beam.FROM=0 -5e-11', 'LINE.beam.TO=1 -5e-11', 'INITIAL.beam.VELOCITY=0 -1',
                   'TIME.END=1e-3'], bound=1e-10, fast=False, defect='D1'))

    # 5. Grazing: zero normal velocity against the obstacle, tangential motion.
    c.append(Case('graze_ball_on', 'graze', 'point mass on the ground, velocity (1, 0)', ball,
                  ['NODE.ball.AT=0 0', 'INITIAL.ball.VELOCITY=1 0'], bound=1e-12, fast=True,
                  checks=[ball_final_velocity(1, 0, 1e-12), ball_stays(0, 1e-12)]))
    c.append(Case('graze_ball_1e-12', 'graze', 'point mass 1e-12 m above the ground, velocity (1, 0)', ball,
                  ['NODE.ball.AT=0 1e-12', 'INITIAL.ball.VELOCITY=1 0'], bound=1e-12, fast=True,
                  checks=[ball_final_velocity(1, 0, 1e-12), ball_stays(0, 1e-12)]))
    c.append(Case('graze_ball_gravity', 'graze', 'point mass on the ground under gravity, velocity (1, 0)', ball,
                  ['NODE.ball.AT=0 0', 'INITIAL.ball.VELOCITY=1 0', 'GRAVITY.GY=-9.81', 'TIME.END=1'],
                  bound=1e-12, fast=True, checks=[ball_final_velocity(1, 0, 1e-9), ball_stays(0, 1e-12)]))
    c.append(Case('graze_beam', 'graze', 'flat beam on the ground (21 nodes), velocity (1, 0), gravity', fb,
                  ['LINE.beam.FROM=0 0', 'LINE.beam.TO=1 0', 'INITIAL.beam.VELOCITY=1 0'], bound=1e-10, fast=True))
    c.append(Case('graze_beam_nogravity', 'graze', 'flat beam on the ground (21 nodes), velocity (1, 0), no gravity',
                  fb, ['LINE.beam.FROM=0 0', 'LINE.beam.TO=1 0', 'INITIAL.beam.VELOCITY=1 0', 'GRAVITY.GY=0'],
                  bound=1e-11, fast=True, checks=[count_events('establish', 0, 0)],
                  note='DOUBLE round-off of the rigid translation through K0 (docs/precision.md)'))

    # 6. 100 nodes impacting at once.
    for mode, fast in [('PAPER', True), ('PERSIST', False), ('OFF', False)]:
        c.append(Case('impact100_%s' % mode.lower(), 'impact100',
                      'flat beam of 99 BEAM2 landing: 100 OBSTACLE nodes, IMPACT %s' % mode, flat,
                      ['LINE.beam.ELEMENTS=99', 'TIME.END=0.08', 'OUTPUT.FIELDS=0', 'SCHEME.IMPACT=' + mode],
                      bound=1e-10 if mode != 'OFF' else None, fast=fast,
                      checks=[simultaneous(100), first_establish(math.sqrt(2 * 0.02 / G), 1e-5)],
                      note='' if mode != 'OFF' else 'OFF loses the impact energy by design: no bound'))

    # 7. 1e6 steps of small scenes.
    c.append(Case('long_osc_1e6', 'long', 'oscillator, 1e6 steps of T/314 (3183 periods), HISTORY EVERY 1000',
                  osc, ['TIME.STEP=0.01', 'TIME.END=10000', 'OUTPUT.HISTORY=EVERY 1000'], bound=1e-9, fast=True,
                  checks=[osc_exact(0.01, 1e-8), total_steps(10 ** 6)]))
    c.append(Case('long_bounce_1e6', 'long', 'mass_bounce.dat, 1e6 steps (1300 s, ~1440 impacts), HISTORY EVERY 1000', 'inputs/mass_bounce.dat', ['TIME.END=1300', 'OUTPUT.HISTORY=EVERY 1000'], bound=1e-10,
                  fast=False, timeout=600,
                  checks=[bounce_period(math.sqrt(2 / G), tb, 1.3e-3, 1300.0), total_steps(10 ** 6)]))

    # 8. Perfect plasticity, strain increment ~1000 x the yield strain in one step.
    pbar = SC + 'plastic_bar.dat'
    ey = 2.5e8 / 2.1e11
    c.append(Case('plastic_bar_1step_elastic_iter', 'plastic',
                  'massless perfectly plastic bar + 1 kg, one step of ~990 yield strains, ITERATION ELASTIC, '
                  'SCHEME RETRY 0', pbar, ['SCHEME.RETRY=0'], expect='refuse', code=1, message='did not converge',
                  fast=True, note='K0 iteration contracts by EA/L / (EA/L + 4m/h^2) = 0.84 per iteration'))
    c.append(Case('plastic_bar_1step_retry', 'plastic',
                  'the same with the default SCHEME RETRY 4: the step is taken again as 2 sub-steps (K0 iteration '
                  'contracts by EA/L / (EA/L + 16m/h^2) = 0.57)', pbar, [], bound=1e-9, fast=True,
                  checks=[plastic_path_energy(1.0, 1190.0, 2.5e4, ey, 1.0, 1e-3)]))
    c.append(Case('plastic_bar_1step', 'plastic',
                  'the same, ITERATION TANGENT', pbar, ['SCHEME.ITERATION=TANGENT'], bound=1e-12, fast=True,
                  checks=[plastic_path_energy(1.0, 1190.0, 2.5e4, ey, 1.0, 1e-3)]))
    c.append(Case('plastic_bar_1step_n100', 'plastic', 'the same, SUBSTEPS 100 (AUTO picks 100 too)', pbar,
                  ['SCHEME.ITERATION=TANGENT', 'MODEL.bar.SUBSTEPS=100'], bound=1e-12, fast=False,
                  checks=[plastic_path_energy(1.0, 1190.0, 2.5e4, ey, 1.0, 1e-3)]))
    c.append(Case('plastic_bar_100steps', 'plastic',
                  'the same over 0.1 s (stops at 0.048 s, then elastic), 100 steps, ITERATION ELASTIC, '
                  'MAX_ITERATIONS 1000', pbar, ['SCHEME.MAX_ITERATIONS=1000', 'TIME.END=0.1'], bound=1e-8, fast=True,
                  note='balance at the solver tolerance (1e-10 x force scale)'))
    c.append(Case('plastic_bar_100steps_tangent', 'plastic', 'the same with ITERATION TANGENT', pbar,
                  ['SCHEME.ITERATION=TANGENT', 'TIME.END=0.1'], bound=1e-8, fast=False, defect='D2'))
    spl = 'inputs/spring_plastic.dat'
    c.append(Case('plastic_spring_1step', 'plastic',
                  'spring_plastic.dat (Fy = 100 N, ey = 1 cm), v0 = 1e4 m/s, one step of 1e-3 s (~1000 ey)', spl,
                  ['INITIAL.tip.VELOCITY=1e4 0', 'TIME.STEP=1e-3', 'TIME.END=1e-3'], bound=1e-9, fast=True,
                  checks=[plastic_path_energy(1.0, 1e4, 100.0, 0.01, 1.0, 1e-6)]))
    c.append(Case('plastic_spring_auto_1step', 'plastic', 'the same with SUBSTEPS AUTO', spl,
                  ['INITIAL.tip.VELOCITY=1e4 0', 'TIME.STEP=1e-3', 'TIME.END=1e-3', 'MODEL.spring.SUBSTEPS=AUTO'],
                  bound=1e-9, fast=False, checks=[plastic_path_energy(1.0, 1e4, 100.0, 0.01, 1.0, 1e-6)]))
    rev = ['INITIAL.tip.VELOCITY=10 0', 'TIME.STEP=0.06283185307179587', 'TIME.END=1.2566370614359172']
    c.append(Case('plastic_spring_reverse', 'plastic',
                  'spring_plastic.dat, v0 = 10 m/s (100 x the elastic energy), h = T (20 steps, load reversals), '
                  'MAX_ITERATIONS 1000', spl, rev + ['SCHEME.MAX_ITERATIONS=1000'], bound=1e-9, fast=True))
    c.append(Case('plastic_spring_reverse_tangent', 'plastic', 'the same with ITERATION TANGENT', spl,
                  rev + ['SCHEME.ITERATION=TANGENT', 'SCHEME.MAX_ITERATIONS=100'], bound=1e-9, fast=False,
                  defect='D2'))
    return c


CASES = build_cases()


# ----------------------------------------------------------------------------------------------
# Running
# ----------------------------------------------------------------------------------------------

def run_case(case, outdir):
    """Run one case; returns a dict with the measured numbers and the assertions."""
    if os.path.exists(outdir):
        shutil.rmtree(outdir)
    os.makedirs(os.path.dirname(outdir), exist_ok=True)
    cmd = [REBOND, case.scene, '-o', outdir, '--quiet']
    for s in case.sets:
        cmd += ['--set', s]
    t0 = time.time()
    res = {'case': case, 'dir': outdir, 'asserts': [], 'rel_balance': None, 'steps': None, 'bad': None,
           'message': '', 'rc': None}
    try:
        p = run_limited(cmd, case.timeout, cwd=ROOT, text=True)
        res['rc'] = 'timeout' if p.returncode == -signal.SIGXCPU else p.returncode
        err = [ln for ln in p.stderr.strip().splitlines() if ln.strip() and not ln.startswith('STOP ')]
        res['message'] = err[-1] if err else ''
    except subprocess.TimeoutExpired:
        res['rc'] = 'timeout'
        res['message'] = 'no end after %d s' % case.timeout
    if res['rc'] == 'timeout':
        res['message'] = 'no end within %d s of CPU time' % case.timeout
    res['wall'] = time.time() - t0
    A = res['asserts']
    name = 'extremes/' + case.key
    if case.expect == 'refuse':
        ok = res['rc'] == case.code and case.message.lower() in res['message'].lower()
        A.append((name + ': refused (exit %d, "%s")' % (case.code, case.message), ok,
                  'exit %s, message: %s' % (res['rc'], res['message'][:300])))
        if case.code == 2:
            written = os.path.isdir(outdir) and len(os.listdir(outdir)) > 0
            A.append((name + ': nothing written on an input error', not written, 'files in %s' % outdir))
        elif os.path.exists(os.path.join(outdir, 'history.csv')):
            o = Out(outdir)
            res['bad'] = o.bad
            A.append((name + ': results kept are finite', o.bad == 0, '%d non-finite values' % o.bad))
        return res
    A.append((name + ': exit 0', res['rc'] == 0, 'exit %s: %s' % (res['rc'], res['message'][:300])))
    if res['rc'] != 0 or not os.path.exists(os.path.join(outdir, 'history.csv')):
        return res
    try:
        o = Out(outdir)
    except (OSError, ValueError, IndexError) as exc:
        A.append((name + ': outputs readable', False, str(exc)))
        return res
    res['bad'] = o.bad
    res['steps'] = int(o.hist['step'][-1])
    A.append((name + ': no NaN or Inf', o.bad == 0, '%d non-finite values' % o.bad))
    if case.bound is not None:
        rb = o.rel_balance()
        res['rel_balance'] = rb
        A.append((name + ': max |balance| / max(kinetic + internal) <= %.0e' % case.bound,
                  math.isfinite(rb) and rb <= case.bound, 'measured %.3e' % rb))
    else:
        res['abs_balance'] = float(np.max(np.abs(o.hist['balance'])))
        rb = o.rel_balance()
        res['rel_balance'] = rb if math.isfinite(rb) else None
        if case.group == 'gap':
            A.append((name + ': balance == 0', res['abs_balance'] == 0.0, 'max |balance| %.3e J' % res['abs_balance']))
    for chk in case.checks:
        try:
            cname, ok, detail = chk(o)
        except (KeyError, IndexError, ValueError) as exc:
            cname, ok, detail = chk.__name__, False, 'check crashed: %s' % exc
        A.append((name + ': ' + cname, ok, detail))
    return res


def verdict(res):
    return all(ok for _, ok, _ in res['asserts'])


def print_asserts(res):
    for n, ok, detail in res['asserts']:
        tag = ' [known defect %s, docs/extremes.md]' % res['case'].defect if res['case'].defect else ''
        print(('PASS ' + n) if ok else ('FAIL %s: %s%s' % (n, detail, tag)))
        if ok and detail:
            print('#   ' + detail)
    sys.stdout.flush()


def markdown(results):
    lines = ['| case | what | expected | exit | steps | wall (s) | max \\|balance\\|/E (bound) | checks | verdict |',
             '|---|---|---|---|---|---|---|---|---|']
    for r in results:
        c = r['case']
        if c.expect == 'refuse':
            exp = 'refuse (exit %d)' % c.code
        else:
            exp = 'ok'
        rb = r.get('rel_balance')
        if c.expect == 'refuse':
            bal = '—'
        elif rb is None:
            bal = ('%.1e J abs.' % r['abs_balance']) if 'abs_balance' in r else 'n/a'
        else:
            bal = '%.2e (%s)' % (rb, '%.0e' % c.bound if c.bound is not None else 'none')
        checks = []
        for n, ok, detail in r['asserts']:
            short = n.split(': ', 1)[1] if ': ' in n else n
            if c.expect == 'refuse' and short.startswith('refused'):
                checks.append('%s: %s' % ('ok' if ok else 'FAIL', r['message'][:160].replace('|', '/')))
            elif any(short.startswith(k) for k in ('exit 0', 'no NaN', 'max |balance|')):
                if not ok:
                    checks.append('FAIL %s: %s' % (short, detail))
            else:
                checks.append('%s%s: %s' % ('' if ok else 'FAIL ', short, detail.replace('|', '\\|')))
        lines.append('| `%s` | %s | %s | %s | %s | %.2f | %s | %s | %s |' % (
            c.key, c.what, exp, r['rc'], r['steps'] if r['steps'] is not None else '—', r['wall'], bal,
            '<br>'.join(checks) if checks else '—',
            ('PASS' if verdict(r) else '**FAIL**') + (' (defect %s)' % c.defect if c.defect else '')))
    return '\n'.join(lines) + '\n'


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--fast', action='store_true', help='only the fast subset (make test)')
    ap.add_argument('--only', help='comma-separated case keys (prefixes allowed)')
    ap.add_argument('--out', help='keep the runs in OUT/<case>/ (default: a temporary folder)')
    ap.add_argument('--markdown', help='write the table of outcomes to this file')
    ap.add_argument('--jobs', type=int, default=1, help='cases run at once (default 1)')
    ap.add_argument('--list', action='store_true', help='list the cases and exit')
    ap.add_argument('--strict', action='store_true', help='exit 1 when a case fails (make extremes)')
    ap.add_argument('--doc', help='also put the table into this Markdown file, between the markers '
                                  '<!-- BEGIN extremes table --> and <!-- END extremes table -->')
    a = ap.parse_args(argv)
    cases = [c for c in CASES if (c.fast and c.defect is None) or not a.fast]
    if a.only:
        keys = a.only.split(',')
        cases = [c for c in cases if any(c.key.startswith(k) for k in keys)]
    if a.list:
        for c in cases:
            print('%-34s %-9s %s' % (c.key, c.group, c.what))
        return 0
    if not os.access(REBOND, os.X_OK):
        print('CRASH bin/rebond not built (%s)' % REBOND)
        return 2
    tmp = None
    out = a.out
    if out is None:
        tmp = tempfile.TemporaryDirectory(prefix='rebond_extremes_')
        out = tmp.name
    t0 = time.time()
    with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        futures = [ex.submit(run_case, c, os.path.join(out, c.key)) for c in cases]
        results = []
        for f in futures:
            r = f.result()
            print_asserts(r)
            results.append(r)
    n_fail = sum(1 for r in results if not verdict(r))
    print('# %d cases, %d failed, %.1f s' % (len(results), n_fail, time.time() - t0))
    if a.markdown:
        os.makedirs(os.path.dirname(os.path.abspath(a.markdown)), exist_ok=True)
        with open(a.markdown, 'w') as f:
            f.write(markdown(results))
        print('# table written to %s' % a.markdown)
    if a.doc and os.path.exists(a.doc):
        doc = open(a.doc).read()
        b, e = '<!-- BEGIN extremes table -->', '<!-- END extremes table -->'
        if b in doc and e in doc:
            stamp = ('Generated by `make extremes` on %s: %d cases, %d failed, %.0f s.\n\n'
                     % (time.strftime('%Y-%m-%d'), len(results), n_fail, time.time() - t0))
            doc = doc[:doc.index(b) + len(b)] + '\n' + stamp + markdown(results) + doc[doc.index(e):]
            with open(a.doc, 'w') as f:
                f.write(doc)
            print('# table put into %s' % a.doc)
    return 1 if (a.strict and n_fail) else 0


if __name__ == '__main__':
    sys.exit(main())
