#!/usr/bin/env python3
"""The energy correction in large displacements against plain Newmark, by step (`make large`),
and the snapshots of inputs/ring_impact.dat (docs/figures/ring_impact.png).

Runs tests/scenes/large_bar/pendulum.dat (a stiff bar pendulum released at 90 degrees, period
T = 2.367836 s) over 24 s at steps from T/2400 to T/10, with SCHEME ENERGY_CORRECTION ON and OFF
(TOLERANCE 1e-10), and writes the table and the figure docs/figures/large_energy_vs_h.png into
docs/large-displacements.md between the markers <!-- study:begin --> and <!-- study:end -->.
CPU: user + system time of each run.

    /usr/bin/python3 tools/large_study.py [--steps 1e-3 2.4e-3 ...] [--doc docs/large-displacements.md]
"""
import argparse
import os
import resource
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REBOND = os.path.join(ROOT, 'bin', 'rebond')
SCENE = 'tests/scenes/large_bar/pendulum.dat'
PERIOD = 2.367836


def run(h, mode, work):
    """(exit code, steps done, max |balance|/E, iterations, retried steps, CPU s)."""
    out = os.path.join(work, '%s_%s' % (h, mode))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([REBOND, SCENE, '-o', out, '--quiet', '--set', 'TIME.STEP=%s' % h, '--set', 'TIME.END=24',
                        '--set', 'SCHEME.ENERGY_CORRECTION=%s' % mode, '--set', 'SCHEME.TOLERANCE=1e-10'],
                       cwd=ROOT, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    h_ = np.atleast_1d(np.genfromtxt(os.path.join(out, 'history.csv'), delimiter=',', names=True))
    e = np.max(h_['kinetic'] + h_['internal'])
    bal = np.max(np.abs(h_['balance'])) / e if e > 0 and len(h_) > 1 else float('nan')
    return p.returncode, int(h_['step'][-1]), float(h_['time'][-1]), bal, int(h_['iterations'].sum()), \
        int(np.sum(h_['substeps'] > 1)), cpu


def ring_figure(path):
    """The ring of inputs/ring_impact.dat every 25 steps (5 ms), from its fields.h5."""
    import h5py
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    with tempfile.TemporaryDirectory() as work:
        subprocess.run([REBOND, 'inputs/ring_impact.dat', '-o', work, '--quiet'], cwd=ROOT, check=True)
        with h5py.File(os.path.join(work, 'fields.h5'), 'r') as f:
            x = f['mesh/coordinates'][:, :2]
            top = f['mesh/topology'][:].reshape(-1, 5)[:, 1:]      # QUAD4: type code, then 4 nodes
            steps = sorted(k for k in f if k.startswith('step_'))
            times = f['times'][:]
            fig, ax = plt.subplots(figsize=(7.0, 4.2))
            for k, (name, colour) in enumerate(zip(steps[::2], ['k', 'tab:blue', 'tab:red', 'tab:green'])):
                p = x + f[name + '/displacement'][:, :2]
                for e in top:
                    q = p[list(e) + [e[0]]]
                    ax.plot(q[:, 0], q[:, 1], colour, lw=0.4)
                ax.plot([], [], colour, label='t = %.0f ms' % (1e3 * times[2 * k]))
    ax.axvline(0.105, color='gray', lw=2)
    ax.set_aspect('equal')
    ax.legend(loc='center left', fontsize=8)
    ax.set_title('inputs/ring_impact.dat: elastic ring against a wall (KINEMATICS LARGE)')
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--steps', nargs='+', default=['1e-3', '2.4e-3', '1.2e-2', '2.4e-2', '0.12', '0.24'])
    ap.add_argument('--doc', default=os.path.join(ROOT, 'docs', 'large-displacements.md'))
    ap.add_argument('--figure', default=os.path.join(ROOT, 'docs', 'figures', 'large_energy_vs_h.png'))
    a = ap.parse_args()
    if not os.access(REBOND, os.X_OK):
        sys.exit('large_study: bin/rebond not found (make first)')
    rows = ['| h (of the period) | correction | outcome | steps | max \\|balance\\|/E | iterations | retried steps | CPU s |',
            '|---|---|---|---|---|---|---|---|']
    curve = {'ON': [], 'OFF': []}
    with tempfile.TemporaryDirectory() as work:
        for h in a.steps:
            for mode in ('ON', 'OFF'):
                rc, n, t, bal, it, ret, cpu = run(h, mode, work)
                outcome = 'ok' if rc == 0 else 'exit %d after t = %.3g s' % (rc, t)
                rows.append('| %s (T/%.0f) | %s | %s | %d | %.1e | %d | %d | %.2f |'
                            % (h, PERIOD / float(h), mode, outcome, n, bal, it, ret, cpu))
                print(rows[-1], flush=True)
                if rc == 0:
                    curve[mode].append((float(h), bal))
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for mode, style in (('ON', 'o-'), ('OFF', 's--')):
        if curve[mode]:
            x, y = zip(*curve[mode])
            ax.loglog(np.array(x) / PERIOD, np.maximum(y, 1e-16), style,
                      label='energy correction %s' % mode + (' (plain Newmark)' if mode == 'OFF' else ''))
    ax.set_xlabel('h / T (T = 2.368 s, the 90° pendulum period)')
    ax.set_ylabel('max |balance| / E over 24 s')
    ax.set_title('Stiff bar pendulum, KINEMATICS LARGE, TOLERANCE 1e-10')
    ax.grid(True, which='both', alpha=0.3)
    ax.legend()
    fig.tight_layout()
    os.makedirs(os.path.dirname(a.figure), exist_ok=True)
    fig.savefig(a.figure, dpi=110)
    ring_figure(os.path.join(os.path.dirname(a.figure), 'ring_impact.png'))
    text = open(a.doc).read()
    begin, end = '<!-- study:begin -->', '<!-- study:end -->'
    rel = os.path.relpath(a.figure, os.path.dirname(a.doc))
    block = '\n'.join(['', 'Generated by `make large` (`tools/large_study.py`). Command per run:', '',
                       '    bin/rebond %s --set TIME.STEP=h --set TIME.END=24 \\' % SCENE,
                       '        --set SCHEME.ENERGY_CORRECTION=ON|OFF --set SCHEME.TOLERANCE=1e-10', ''] + rows +
                      ['', '![energy error against the step](%s)' % rel, '', '*Max |balance| / E against h / T, with and '
                       'without the energy correction; runs that stopped are left out of the curves.*', ''])
    if begin in text and end in text:
        text = text[:text.index(begin) + len(begin)] + block + text[text.index(end):]
        with open(a.doc, 'w') as f:
            f.write(text)
        print('wrote', a.doc, 'and', a.figure)
    else:
        print('markers not found in', a.doc, file=sys.stderr)
        sys.exit(1)


if __name__ == '__main__':
    main()
