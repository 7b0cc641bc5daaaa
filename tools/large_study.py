#!/usr/bin/env python3
"""The energy correction in large displacements against plain Newmark, by step (`make large`),
and the snapshots of inputs/ring_impact.dat (docs/figures/ring_impact.png).

The corotational BEAM2 scenes (inputs/beam_flying.dat, beam_drop_inclined_large.dat,
cantilever_large.dat) from T/1000 to T/10 of their first period, correction ON and OFF: the
table between <!-- beams:begin --> and <!-- beams:end -->, docs/figures/large_beams_vs_h.png
(energy error and CPU against h) and docs/figures/large_beams.png (the beams in motion).

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

from docblock import replace_block

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REBOND = os.path.join(ROOT, 'bin', 'rebond')
SCENE = 'tests/scenes/large_bar/pendulum.dat'
PERIOD = 2.367836


def run(h, mode, work, scene=SCENE, sets=('TIME.END=24', 'SCHEME.TOLERANCE=1e-10')):
    """(exit code, steps done, time reached, max |balance|/E, iterations, retried steps, CPU s,
    history)."""
    out = os.path.join(work, '%s_%s_%s' % (os.path.basename(scene), h, mode))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    cmd = [REBOND, scene, '-o', out, '--quiet', '--set', 'TIME.STEP=%s' % h, '--set', 'SCHEME.ENERGY_CORRECTION=%s' % mode]
    for st in sets:
        cmd += ['--set', st]
    p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    h_ = np.atleast_1d(np.genfromtxt(os.path.join(out, 'history.csv'), delimiter=',', names=True))
    e = np.max(h_['kinetic'] + h_['internal'])
    bal = np.max(np.abs(h_['balance'])) / e if e > 0 and len(h_) > 1 else float('nan')
    return p.returncode, int(h_['step'][-1]), float(h_['time'][-1]), bal, int(h_['iterations'].sum()), \
        int(np.sum(h_['substeps'] > 1)), cpu, h_


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


BEAMS = (('inputs/beam_flying.dat', 1.256, 'beam_flying (free flying beam, 15 s; T = 1.256 s, first free-free bending mode)'),
         ('inputs/beam_drop_inclined_large.dat', 0.019, 'beam_drop_inclined_large (45° beam on the ground, 0.6 s; '
          'T = 19 ms, first bending mode)'),
         ('inputs/cantilever_large.dat', 1.19, 'cantilever_large (bent to P L²/EI = 5 and released, 16 s; T1 = 1.19 s)'))


def beams_study(work, figure):
    """The corotational BEAM2 scenes from T/1000 to T/10, ON and OFF: table rows and the figure."""
    rows = ['| scene | h | correction | outcome | steps | max \\|balance\\|/E | angular momentum drift after t = 5 s '
            '| iterations per step | retried steps | CPU s |', '|---|---|---|---|---|---|---|---|---|---|']
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.2))
    for (scene, period, label), colour in zip(BEAMS, ('tab:blue', 'tab:red', 'tab:green')):
        curve = {'ON': [], 'OFF': []}
        cpu_on = []
        for div in (1000, 300, 100, 30, 10):
            h = '%.4g' % (period / div)
            for mode in ('ON', 'OFF'):
                rc, n, t, bal, it, ret, cpu, hist = run(h, mode, work, scene, ('OUTPUT.HISTORY=1',))
                drift = '–'
                if 'flying' in scene and rc == 0:
                    am = hist['angular_momentum'][hist['time'] >= 5.0 - 1e-9]
                    drift = '%.1e' % ((am.max() - am.min()) / abs(am[0]))
                outcome = 'ok' if rc == 0 else 'exit %d after t = %.3g s' % (rc, t)
                rows.append('| %s | T/%d = %s | %s | %s | %d | %.1e | %s | %.1f | %d | %.2f |'
                            % (os.path.basename(scene), div, h, mode, outcome, n, bal, drift, it / max(n, 1), ret, cpu))
                print(rows[-1], flush=True)
                if rc == 0:
                    curve[mode].append((1.0 / div, bal))
                    if mode == 'ON':
                        cpu_on.append((1.0 / div, cpu))
        name = os.path.basename(scene)[:-4]
        for mode, style in (('ON', 'o-'), ('OFF', 's--')):
            if curve[mode]:
                x, y = zip(*curve[mode])
                axes[0].loglog(x, np.maximum(y, 1e-16), style, color=colour, label='%s %s' % (name, mode))
        if cpu_on:
            x, y = zip(*cpu_on)
            axes[1].loglog(x, y, 'o-', color=colour, label=name)
    axes[0].set_xlabel('h / T')
    axes[0].set_ylabel('max |balance| / E')
    axes[0].set_title('Corotational BEAM2: energy error, correction ON / OFF')
    axes[1].set_xlabel('h / T')
    axes[1].set_ylabel('CPU s (correction ON)')
    axes[1].set_title('Cost of the run against the step')
    for ax in axes:
        ax.grid(True, which='both', alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(figure, dpi=100)
    return rows


def beam_snapshots(path):
    """beam_flying every second and beam_drop_inclined_large every 50 ms, from probes-free fields."""
    import h5py
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.6))
    for ax, scene, every, title in ((axes[0], 'inputs/beam_flying.dat', 100, 'beam_flying: every 1 s (h = 0.01 s)'),
                                    (axes[1], 'inputs/beam_drop_inclined_large.dat', 1000,
                                     'beam_drop_inclined_large: every 50 ms')):
        with tempfile.TemporaryDirectory() as work:
            subprocess.run([REBOND, scene, '-o', work, '--quiet', '--set', 'OUTPUT.FIELDS=%d' % every], cwd=ROOT, check=True)
            with h5py.File(os.path.join(work, 'fields.h5'), 'r') as f:
                x = f['mesh/coordinates'][:, :2]
                steps = sorted(k for k in f if k.startswith('step_'))
                cmap = plt.get_cmap('viridis')
                for k, name in enumerate(steps):
                    p = x + f[name + '/displacement'][:, :2]
                    ax.plot(p[:, 0], p[:, 1], '-', color=cmap(k / max(len(steps) - 1, 1)), lw=1.2)
        if 'drop' in scene:
            ax.axhline(0.0, color='gray', lw=2)
        ax.set_aspect('equal')
        ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--steps', nargs='+', default=['1e-3', '2.4e-3', '1.2e-2', '2.4e-2', '0.12', '0.24'])
    ap.add_argument('--doc', default=os.path.join(ROOT, 'docs', 'large-displacements.md'))
    ap.add_argument('--figure', default=os.path.join(ROOT, 'docs', 'figures', 'large_energy_vs_h.png'))
    ap.add_argument('--beams-only', action='store_true', help='only the BEAM2 study')
    a = ap.parse_args()
    if not os.access(REBOND, os.X_OK):
        sys.exit('large_study: bin/rebond not found (make first)')
    rows = ['| h (of the period) | correction | outcome | steps | max \\|balance\\|/E | iterations | retried steps | CPU s |',
            '|---|---|---|---|---|---|---|---|']
    curve = {'ON': [], 'OFF': []}
    figdir = os.path.dirname(a.figure)
    os.makedirs(figdir, exist_ok=True)
    with tempfile.TemporaryDirectory() as work:
        brows = beams_study(work, os.path.join(figdir, 'large_beams_vs_h.png'))
    beam_snapshots(os.path.join(figdir, 'large_beams.png'))
    rel = os.path.relpath(figdir, os.path.dirname(a.doc))
    bblock = '\n'.join(['', 'Generated by `make large` (`tools/large_study.py`). Command per run:', '',
                        '    bin/rebond SCENE --set TIME.STEP=h --set SCHEME.ENERGY_CORRECTION=ON|OFF --set OUTPUT.HISTORY=1', ''] + brows +
                       ['', '![energy error and CPU against the step](%s/large_beams_vs_h.png)' % rel, '',
                        '![the beams in flight and on the ground](%s/large_beams.png)' % rel, ''])
    replace_block(a.doc, '<!-- beams:begin -->', '<!-- beams:end -->', bblock)
    if a.beams_only:
        return
    with tempfile.TemporaryDirectory() as work:
        for h in a.steps:
            for mode in ('ON', 'OFF'):
                rc, n, t, bal, it, ret, cpu, _ = run(h, mode, work)
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
    rel = os.path.relpath(a.figure, os.path.dirname(a.doc))
    block = '\n'.join(['', 'Generated by `make large` (`tools/large_study.py`). Command per run:', '',
                       '    bin/rebond %s --set TIME.STEP=h --set TIME.END=24 \\' % SCENE,
                       '        --set SCHEME.ENERGY_CORRECTION=ON|OFF --set SCHEME.TOLERANCE=1e-10', ''] + rows +
                      ['', '![energy error against the step](%s)' % rel, '', '*Max |balance| / E against h / T, with and '
                       'without the energy correction; runs that stopped are left out of the curves.*', ''])
    replace_block(a.doc, '<!-- study:begin -->', '<!-- study:end -->', block)


if __name__ == '__main__':
    main()
