#!/usr/bin/python3
"""The contact comparison table of docs/contact.md (issue 11), by `make validation`.

    tools/contact_table.py [--out results/contact_table] [--doc docs/contact-table.md]
                           [--sizes 20 40 80 160 320]
                           [--modes AUTO PAPER/CONSISTENT ... SYMMETRIC/MIXED]
                           [--cfl 0.1]
    tools/contact_table.py --trade [--doc docs/contact-trade.md]   (and docs/figures/sdnv100_default.png)

Three impact benchmarks with exact solutions, generated here, each run in every impact mode
at every mesh size with h = cfl x dx/c (a mode MODE/MASS runs with that MODEL MASS, MODE alone
with the scene's default mass, TUNED on these bars at c h/dx <= 1):
- bar: code_aster SDNV100's free bar on a rigid wall (L 0.2 m, 0.02 x 0.02 m, E 2e11, nu 0,
  rho 8000, v0 -100 m/s, gap 2 mm, consistent mass). Exact: contact [2e-5, 1e-4] s, force
  rho c v0 A = 1.6e6 N, rebound +100 m/s.
- clamped: a 1D bar (L = E = rho = A = 1) clamped at x = 1, released from u0 = 1/2 - x/2 with
  the contact u(0) >= 0. Exact: energy 1/8, contact on [1, 2] (then [3k+1, 3k+2]), contact
  stress -1/2, v(0) = +1/2 after release.
- two bars: bar a (L 0.2 m, steel as above) at +10 m/s hits bar b at rest end to end (GAP).
  Exact: contact 2L/c = 8e-5 s, a stops, b leaves at +10 m/s.
--trade: the step against the accuracy on the bar (c h/dx 0.1 to 1, 20 to 320 elements) for the
default (no MASS: TUNED, alpha = 1/2 + (c h/dx)^2, and AUTO), the former default (consistent mass,
AUTO), SYMMETRIC with MASS MIXED, and PERSIST with MASS TUNED (docs/contact.md, "The default mass").
Columns: max |balance| / energy, contact onsets (one physical impact), force std/mean and mean
force error while the contact holds (its inner 80 %), rebound error (momentum after release against the exact
one), release error in steps, CPU time (user + system of the run).
"""
import argparse
import csv
import os
import resource
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REBOND = os.path.join(ROOT, 'bin', 'rebond')


def mass_words(mass):
    """MODEL's MASS parameter, or nothing for the default (TUNED on these bars at c h/dx <= 1)."""
    return ' MASS ' + mass if mass else ''


def bar_scene(n, cfl, mode, mass=None, shift=0.0):
    """shift: the bar that much further from the wall (m), and the run that much longer (at v0)."""
    c = (2e11 / 8000) ** 0.5
    h = cfl * 0.2 / n / c
    return h, f"""LINE bar FROM {0.002 + shift!r} 0 TO {0.202 + shift!r} 0 ELEMENTS {n} TYPE BAR2
MATERIAL steel ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000
SECTION rod AREA 4e-4
MODEL bar MATERIAL steel SECTION rod{mass_words(mass)}
FIX bar UY
INITIAL bar VELOCITY -100 0
OBSTACLE wall NODES bar.start POINT 0 0 NORMAL 1 0
TIME STEP {h!r} END {1.3e-4 + shift / 100.0!r}
SCHEME IMPACT {mode}
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0
"""


def clamped_scene(n, cfl, mode, mass=None):
    h = cfl / n
    lines = []
    for i in range(n + 1):
        x = i / n
        lines.append(f'NODE p{i} AT {x!r} 0')
        lines.append(f'INITIAL p{i} DISPLACEMENT {0.5 - x / 2!r} 0')
    for i in range(n):
        lines.append(f'ELEMENT e{i} TYPE BAR2 NODES p{i} p{i + 1}')
    lines.append('GROUP bar ELEMENTS ' + ' '.join(f'e{i}' for i in range(n)))
    lines.append('GROUP every NODES ' + ' '.join(f'p{i}' for i in range(n + 1)))
    lines += ['MATERIAL m ELASTIC YOUNG 1 POISSON 0 DENSITY 1', 'SECTION s AREA 1',
              f'MODEL bar MATERIAL m SECTION s{mass_words(mass)}', 'FIX every UY', f'FIX p{n} UX',
              'OBSTACLE wall NODES p0 POINT 0 0 NORMAL 1 0', f'TIME STEP {h!r} END 2.8',
              f'SCHEME IMPACT {mode}', 'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE p0 UX']
    return h, '\n'.join(lines) + '\n'


def two_bars_scene(n, cfl, mode, mass=None):
    c = (2e11 / 8000) ** 0.5
    h = cfl * 0.2 / n / c
    return h, f"""LINE a FROM 0 0 TO 0.2 0 ELEMENTS {n} TYPE BAR2
LINE b FROM 0.2001 0 TO 0.4001 0 ELEMENTS {n} TYPE BAR2
MATERIAL steel ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000
SECTION rod AREA 4e-4
MODEL a MATERIAL steel SECTION rod{mass_words(mass)}
MODEL b MATERIAL steel SECTION rod{mass_words(mass)}
FIX a UY
FIX b UY
INITIAL a VELOCITY 10 0
GAP touch PAIRS a.end b.start
TIME STEP {h!r} END 1.2e-4
SCHEME IMPACT {mode}
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0
"""


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    out = {}
    for k in (rows[0].keys() if rows else []):
        vals = [r[k] for r in rows]
        try:
            out[k] = np.array([float(v) for v in vals])
        except ValueError:
            out[k] = np.array(vals)
    return out


def run(name, scene, outdir):
    os.makedirs(outdir, exist_ok=True)
    path = os.path.join(outdir, name + '.dat')
    with open(path, 'w') as f:
        f.write(scene)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([REBOND, path, '-o', os.path.join(outdir, name), '--quiet'], capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return p.returncode, p.stderr.strip(), os.path.join(outdir, name), cpu


def measures(kind, out, h, n):
    hist = read(os.path.join(out, 'history.csv'))
    con = read(os.path.join(out, 'contacts.csv'))
    energy = np.max(hist['kinetic'] + hist['internal'])
    bal = np.max(np.abs(hist['balance'])) / energy
    onsets = 0
    with open(os.path.join(out, 'events.csv')) as f:
        onsets = sum(1 for line in f if ',establish,' in line)
    on = np.nonzero(np.abs(con['force_x']) > 0)[0]
    std = np.nan
    mean_err = np.nan
    rel_err = np.nan
    if len(on) >= 5:
        k0, k1 = on[0] + (on[-1] - on[0]) // 10, on[-1] - (on[-1] - on[0]) // 10
        held = con['force_x'][k0:k1 + 1]
        std = held.std() / abs(held.mean()) if held.size and held.mean() != 0 else np.nan
        mean_err = (held.mean() - EXACT_FORCE[kind]) / abs(EXACT_FORCE[kind]) if held.size else np.nan
    if kind == 'bar':
        mass = 8000 * 4e-4 * 0.2
        reb = (hist['momentum_x'][-1] / mass - 100.0) / 100.0
        if len(on):
            rel_err = (con['time'][on[-1]] - 1e-4) / h
    elif kind == 'clamped':
        p = read(os.path.join(out, 'probes.csv'))
        t, u = p['time'], p['p0.UX']
        late = (t > 2.2) & (t < 2.7)
        v = np.polyfit(t[late], u[late], 1)[0] if np.count_nonzero(late) > 2 else np.nan
        reb = (v - 0.5) / 0.5
        first = on[(con['time'][on] < 2.5)] if len(on) else on
        if len(first):
            rel_err = (con['time'][first[-1]] - 2.0) / h
    else:
        mass = 8000 * 4e-4 * 0.2
        # b's momentum after release, from the impulses it received; exact 10 m/s.
        imp = np.sum(-con['impulse_x'])      # the impulse on b (the WITH side) = minus that on a
        reb = (imp / mass - 10.0) / 10.0
        if len(on):
            rel_err = (con['time'][on[-1]] - (1e-5 + 8e-5)) / h
    return bal, onsets, std, mean_err, reb, rel_err


# The exact contact force on the NODES side while the contact holds: rho c v0 A (bar on the wall:
# 8000 x 5000 x 100 x 4e-4 N), the stress 1/2 on A = 1 (clamped bar), half of rho c v A on a, in -x
# (two equal bars at 10 m/s).
EXACT_FORCE = {'bar': 1.6e6, 'clamped': 0.5, 'two': -8.0e4}
SCENES = {'bar': bar_scene, 'clamped': clamped_scene, 'two bars': two_bars_scene}
if os.environ.get('CONTACT_TABLE_ONLY'):
    SCENES = {k: v for k, v in SCENES.items() if k == os.environ['CONTACT_TABLE_ONLY']}


TRADE_CFLS = (0.1, 0.3, 0.5, 0.7071, 1.0)
TRADE_SIZES = (20, 80, 320)
TRADE_MODES = ('AUTO', 'AUTO/CONSISTENT', 'SYMMETRIC/MIXED', 'PERSIST/TUNED')


def trade(out, doc):
    """The step-accuracy trade on the bar (--trade): one table, rows by step, mesh and mode."""
    lines = ["# The step against the accuracy: SDNV100's bar", '',
             'Generated by `make contact-table` (`tools/contact_table.py --trade`). The bar of docs/contact-table.md '
             '(20 to 320 BAR2, exact: rebound +100 m/s, release at 2L/c, force 1.6e6 N) at c h/dx from 0.1 to 1. '
             'AUTO (default): the scene says neither MASS nor IMPACT: the mass is TUNED (alpha = 1/2 + (c h/dx)^2, '
             '1.4999 at c h/dx = 1) and AUTO takes SYMMETRIC on it, PERSIST at c h/dx = 1. AUTO, CONSISTENT: the former '
             'default (AUTO takes MASSLESS); MIXED: MASS MIXED (alpha = 1/2); TUNED: MASS TUNED. The consistent '
             'mass is the tuned one at c h/dx = 1/sqrt(2) = 0.7071. Columns as in docs/contact-table.md; steps = h.', '',
             '| c h/dx | elements | mode | max\\|balance\\|/E | onsets | force std/mean | mean force error '
             '| rebound error | release error (steps) | CPU s |', '|---|---|---|---|---|---|---|---|---|---|']
    for cfl in TRADE_CFLS:
        for n in TRADE_SIZES:
            for spec in TRADE_MODES:
                mode, mass = (spec.split('/') + [None])[:2]
                h, scene = bar_scene(n, cfl, mode, mass)
                name = 'trade_%g_%d_%s_%s' % (cfl, n, mode, mass)
                label = mode + ' (default)' if mass is None else mode + ', ' + mass
                rc, err, path, cpu = run(name, scene, out)
                if rc != 0:
                    lines.append('| %g | %d | %s | failed (exit %d): %s | | | | | | %.2f |' % (cfl, n, label, rc, err[-80:],
                                                                                           cpu))
                    continue
                bal, onsets, std, merr, reb, rel = measures('bar', path, h, n)
                lines.append('| %g | %d | %s | %.1e | %d | %.3f | %+.2f %% | %+.3f %% | %+.1f | %.2f |'
                             % (cfl, n, label, bal, onsets, std, 100 * merr, 100 * reb, rel, cpu))
                print(lines[-1], flush=True)
    lines += phase_table(out)
    with open(doc, 'w') as f:
        f.write('\n'.join(lines) + '\n')
    print('wrote', doc)


PHASES = (0.0, 0.25, 0.5, 0.75)


def phase_table(out):
    """The rebound when the contact starts inside a step: the bar moved away from the wall by a
    fraction of v0 h, so that the impact falls at that phase of its step (SDNV100's 2 mm at its own step
    put it on a step's end: phase 0)."""
    lines = ['', '## The impact inside a step', '',
             "SDNV100's gap, 2 mm at 100 m/s, is 10 steps of 2e-6 s: the impact falls on a step's end. A bar "
             'dropped under gravity, or any other gap, puts it anywhere in its step. Here the bar starts a phase '
             'φ of a step further from the wall (gap = 2 mm + φ v0 h); rebound error, default and MASS CONSISTENT '
             '(AUTO), one onset in every run.', '',
             '| c h/dx | elements | mass | ' + ' | '.join('φ = %g' % f for f in PHASES) + ' |',
             '|---|---|---|' + '---|' * len(PHASES)]
    for cfl in (1.0, 0.5, 0.1):
        for n in (20, 80):
            for mass in (None, 'CONSISTENT'):
                cells = []
                for f in PHASES:
                    h = bar_scene(n, cfl, 'AUTO')[0]
                    text = bar_scene(n, cfl, 'AUTO', mass, shift=f * h * 100.0)[1]   # f steps at v0 = 100 m/s
                    rc, err, path, cpu = run('phase_%g_%d_%s_%g' % (cfl, n, mass, f), text, out)
                    if rc != 0:
                        cells.append('failed (exit %d)' % rc)
                        continue
                    hist = read(os.path.join(path, 'history.csv'))
                    cells.append('%+.3f %%' % (100 * (hist['momentum_x'][-1] / (8000 * 4e-4 * 0.2) / 100.0 - 1)))
                lines.append('| %g | %d | %s | %s |' % (cfl, n, 'default' if mass is None else mass, ' | '.join(cells)))
                print(lines[-1], flush=True)
    return lines


def figure(out, path):
    """SDNV100 at its own settings (inputs/sdnv100.dat): contact force, mean velocity and the contact
    node's displacement, the default mass against MASS CONSISTENT, beside the exact solution."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    scene = os.path.join(ROOT, 'inputs', 'sdnv100.dat')
    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    for label, sets in (('default (mass tuned to the step, AUTO)', []),
                        ('MASS CONSISTENT (AUTO)', ['--set', 'MODEL.bar.MASS=CONSISTENT'])):
        d = os.path.join(out, 'figure_' + ('default' if not sets else 'consistent'))
        p = subprocess.run([REBOND, scene, '-o', d, '--quiet', '--set', 'OUTPUT.FIELDS=0'] + sets, capture_output=True,
                           text=True)
        if p.returncode != 0:
            sys.exit('contact_table: %s failed: %s' % (scene, p.stderr.strip()))
        c, h, pr = read(os.path.join(d, 'contacts.csv')), read(os.path.join(d, 'history.csv')), read(os.path.join(d, 'probes.csv'))
        ax[0].plot(1e6 * c['time'], c['force_x'] / 1e6, '.-', label=label)
        ax[1].plot(1e6 * h['time'], h['momentum_x'] / (8000 * 4e-4 * 0.2), '.-', label=label)
        ax[2].plot(1e6 * pr['time'], 1e3 * pr['bar.start.UX'], '.-', label=label)
    t = np.linspace(0, 130, 1301)
    ax[0].plot(t, np.where((t > 20) & (t < 100), 1.6, 0.0), 'k', lw=0.8, label='exact')
    ax[1].plot(t, np.clip(-100 + 2.5 * (t - 20), -100, 100), 'k', lw=0.8, label='exact')
    ax[2].plot(t, np.where(t < 20, -0.1 * t, np.where(t < 100, -2.0, -2.0 + 0.1 * (t - 100))), 'k', lw=0.8,
               label='exact')
    for a, title in zip(ax, ('contact force (MN)', 'mean velocity (m/s)', 'contact node UX (mm)')):
        a.set_title(title)
        a.set_xlabel('t (µs)')
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.suptitle("code_aster SDNV100's bar at its own settings (20 BAR2, h = dx/c = 2e-6 s)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    print('wrote', path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--out', default=os.path.join(ROOT, 'results', 'contact_table'))
    ap.add_argument('--doc', default=os.path.join(ROOT, 'docs', 'contact-table.md'))
    ap.add_argument('--sizes', type=int, nargs='+', default=[20, 40, 80, 160, 320])
    ap.add_argument('--modes', nargs='+', default=['AUTO', 'AUTO/CONSISTENT', 'PAPER/CONSISTENT', 'PERSIST/CONSISTENT',
                                                   'MASSLESS/CONSISTENT', 'OFF/CONSISTENT', 'MASSLESS/MIXED',
                                                   'SYMMETRIC/MIXED'])
    ap.add_argument('--cfl', type=float, default=0.1)
    ap.add_argument('--trade', action='store_true')
    a = ap.parse_args()
    if not os.access(REBOND, os.X_OK):
        sys.exit('contact_table: bin/rebond not found (make first)')
    if a.trade:
        trade(a.out, a.doc if a.doc != ap.get_default('doc') else os.path.join(ROOT, 'docs', 'contact-trade.md'))
        figure(a.out, os.path.join(ROOT, 'docs', 'figures', 'sdnv100_default.png'))
        return
    lines = ['# Contact benchmarks: impact modes against exact solutions', '',
             'Generated by `make validation` (`tools/contact_table.py --cfl %g`): h = %g dx/c. MODE (default): '
             'the scene says no MASS (TUNED on these bars, docs/contact.md "The default mass"); MODE, MASS: '
             'MODEL … MASS MASS. '
             'Rebound: the momentum after release against the exact one (bar: +100 m/s; clamped bar: v(0) = +1/2; '
             'two bars: b leaves at +10 m/s), relative. Release: last step with a contact force minus the exact '
             'release time, in steps. Force std/mean and mean force error over the inner 80 %% of the contact (exact: 1.6e6 N, 1/2, 8e4 N). CPU: user + system '
             'time of the run. AUTO is the default (`SCHEME IMPACT AUTO`): SYMMETRIC on these bars with the default '
             'or a MIXED mass, MASSLESS with a consistent mass (their contact nodes can all give their mass away).'
             % (a.cfl, a.cfl), '']
    for kind, make in SCENES.items():
        lines += ['## ' + kind, '', '| elements | mode | max\\|balance\\|/E | onsets | force std/mean | mean force error '
                  '| rebound error | release error (steps) | CPU s |', '|---|---|---|---|---|---|---|---|---|']
        for n in a.sizes:
            for spec in a.modes:
                mode, mass = (spec.split('/') + [None])[:2]
                h, scene = make(n, a.cfl, mode, mass)
                name = '%s_%d_%s_%s' % (kind.replace(' ', '_'), n, mode, mass)
                mode = mode + ' (default)' if mass is None else mode + ', ' + mass
                rc, err, out, cpu = run(name, scene, a.out)
                if rc != 0:
                    lines.append('| %d | %s | failed (exit %d): %s | | | | | | %.2f |' % (n, mode, rc, err[-80:], cpu))
                    continue
                bal, onsets, std, merr, reb, rel = measures(kind.split()[0] if kind != 'two bars' else 'two', out, h, n)
                lines.append('| %d | %s | %.1e | %d | %.3f | %+.2f %% | %+.3f %% | %+.1f | %.2f |'
                             % (n, mode, bal, onsets, std, 100 * merr, 100 * reb, rel, cpu))
                print(lines[-1], flush=True)
        lines.append('')
    with open(a.doc, 'w') as f:
        f.write('\n'.join(lines))
    print('wrote', a.doc)


if __name__ == '__main__':
    main()
