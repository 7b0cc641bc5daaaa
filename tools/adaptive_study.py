#!/usr/bin/env python3
"""The adaptive step's trade (issue 36): error against a reference run versus CPU time, for
fixed steps and for TIME ... ADAPTIVE at several tolerances, on six scenes; a table and a
figure per scene, and docs/adaptive-step.md (generated: do not edit).

    /usr/bin/python3 tools/adaptive_study.py [--rebond bin/rebond] [--out results/studies/adaptive]
        [--doc docs/adaptive-step.md] [--figures docs/figures] [--quick]

Error of a run: max over its history rows up to END of |x(t) - x_ref(t)| / max |x_ref|, x a probe
or a history.csv column, x_ref the reference run (a fixed step 16 times below the scene's)
interpolated linearly at the run's times. CPU: user + system seconds of the run's process
(getrusage of the children), not the wall clock. "CPU ratio at equal error": for each fixed
step, the adaptive runs' CPU at that step's error (log-log interpolation between the adaptive
points that bracket it) over the fixed run's CPU.
"""
import argparse
import os
import platform
import re
import resource
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# name, scene, sets, base step, (kind, column), fixed step factors, tolerances, what it is
SCENES = [
    ('bar_impact', 'inputs/bar_impact.dat', ['TIME.END=2e-3'], 1e-6, ('probe', 'bar.end.UX'),
     [4, 2, 1, 0.5, 0.25], [1e-2, 1e-3, 1e-4, 1e-5],
     'a free bar (100 BAR2, lumped mass, PERSIST) on a wall: the far end\'s displacement (contact '
     'from 1e-4 s, release at 4e-4 s, then flight)'),
    ('beam_drop_inclined', 'inputs/beam_drop_inclined.dat', ['TIME.END=0.12'], 1e-5, ('history', 'external'),
     [8, 4, 2, 1, 0.5], [1e-2, 1e-3, 1e-4, 1e-5],
     'the inclined beam drop (20 BEAM2, consistent mass, PAPER): the work of gravity, m g times the centre '
     'of mass\'s fall over 0.12 s (the first impact at 0.064 s and the clatter after it; later the clatter is chaotic and no reference is one)'),
    ('mass_bounce', 'inputs/mass_bounce.dat', ['TIME.END=5'], 1.3e-3, ('probe', 'ball.UY'),
     [4, 2, 1, 0.5, 0.25], [1e-2, 1e-3, 1e-4, 1e-5],
     'the point mass bouncing on the ground (PAPER): its height over 5 s (five bounces)'),
    ('ring_impact', 'inputs/ring_impact.dat', [], 2e-4, ('history', 'momentum_x'),
     [2, 1, 0.5, 0.25], [1e-2, 1e-3, 1e-4],
     'the rubber ring (QUAD4, KINEMATICS LARGE) thrown at a wall: its momentum along the wall\'s normal'),
    ('block_j2', 'inputs/block_j2.dat', [], 1e-5, ('probe', 'block.top_left.UY'),
     [4, 2, 1, 0.5], [1e-2, 1e-3, 1e-4, 1e-5],
     'the plane-strain J2 block under a load pulse (table kinks at 1, 2, 3 ms): the top corner\'s '
     'deflection over 5 ms'),
    ('cantilever_release', 'inputs/cantilever_release.dat', ['TIME.END=2'], 1e-4, ('probe', 'beam.end.UY'),
     [4, 2, 1, 0.5, 0.25], [1e-2, 1e-3, 1e-4, 1e-5],
     'the released cantilever (20 BEAM2, a smooth vibration): the tip deflection over 2 s'),
]


def read_csv(path):
    with open(path) as f:
        names = f.readline().strip().split(',')
    data = np.loadtxt(path, delimiter=',', skiprows=1, ndmin=2)
    return {n: data[:, i] for i, n in enumerate(names)}


def run(rebond, scene, sets, out):
    cmd = [rebond, os.path.join(ROOT, scene), '-o', out]
    for s in sets:
        cmd += ['--set', s]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, capture_output=True, text=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    if p.returncode != 0:
        raise RuntimeError('%s failed (exit %d): %s' % (' '.join(cmd), p.returncode, p.stderr[-400:]))
    m = re.search(r'factorized (\d+) times', p.stdout)
    return cpu, int(m.group(1)) if m else 1


def series(out, kind, col):
    h = read_csv(os.path.join(out, 'history.csv'))
    src = h if kind == 'history' else read_csv(os.path.join(out, 'probes.csv'))
    return src['time'], src[col], h


def study(args, name, scene, sets, h0, what, factors, tols):
    kind, col = what
    base = os.path.join(args.out, name)
    os.makedirs(base, exist_ok=True)
    common = sets + ['OUTPUT.FIELDS=0', 'OUTPUT.HISTORY=EVERY 1']
    ref_out = os.path.join(base, 'reference')
    run(args.rebond, scene, common + ['TIME.STEP=%r' % (h0 / 16)], ref_out)
    tr, xr, _ = series(ref_out, kind, col)
    end = tr[-1]
    scale = np.max(np.abs(xr))
    rows = []

    def measure(label, extra):
        out = os.path.join(base, label)
        cpu, nfac = run(args.rebond, scene, common + extra, out)
        t, x, h = series(out, kind, col)
        keep = t <= end * (1 + 1e-12)
        err = np.max(np.abs(x[keep] - np.interp(t[keep], tr, xr))) / scale
        steps = len(h['step']) - 1
        bal = np.max(np.abs(h['balance'])) / np.max(np.abs(h['kinetic'] + h['internal']))
        hs = h['h'][1:]
        rows.append(dict(label=label, cpu=cpu, err=err, steps=steps, bal=bal, hmin=hs.min(), hmax=hs.max(), nfac=nfac))

    for f in factors:
        measure('fixed_h%g' % f, ['TIME.STEP=%r' % (h0 * f)])
    for tol in tols:
        measure('adaptive_%g' % tol, ['TIME.STEP=%r' % h0, 'TIME.ADAPTIVE=', 'TIME.TOLERANCE=%r' % tol])
    fixed = [r for r in rows if r['label'].startswith('fixed')]
    adapt = sorted([r for r in rows if r['label'].startswith('adaptive')], key=lambda r: r['err'])
    for r in fixed:
        r['ratio'] = np.nan
        e = [a['err'] for a in adapt]
        for a, b in zip(adapt[:-1], adapt[1:]):
            if a['err'] <= r['err'] <= b['err'] and a['err'] > 0:
                w = np.log(r['err'] / a['err']) / np.log(b['err'] / a['err']) if b['err'] > a['err'] else 0.0
                r['ratio'] = np.exp(np.log(a['cpu']) + w * (np.log(b['cpu']) - np.log(a['cpu']))) / r['cpu']
        if np.isnan(r['ratio']) and e and r['err'] >= e[-1]:
            # Even the loosest tolerance is more accurate: its CPU bounds the ratio from above.
            r['ratio'] = min(a['cpu'] for a in adapt if a['err'] <= r['err']) / r['cpu']
            r['bound'] = True
    return rows


def plot(results, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(results), figsize=(4.2 * len(results), 3.8))
    for ax, (name, rows) in zip(np.atleast_1d(axes), results):
        for pre, mk, lab in (('fixed', 'o-', 'fixed step'), ('adaptive', 's-', 'ADAPTIVE')):
            rr = sorted([r for r in rows if r['label'].startswith(pre)], key=lambda r: r['cpu'])
            ax.loglog([r['cpu'] for r in rr], [max(r['err'], 1e-16) for r in rr], mk, label=lab)
        ax.set_title(name, fontsize=10)
        ax.set_xlabel('CPU (s)')
        ax.set_ylabel('error / max |reference|')
        ax.grid(True, which='both', alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def write_doc(args, results):
    lines = ['# The adaptive step: accuracy against CPU', '',
             'Generated by `tools/adaptive_study.py` (`make studies`; do not edit). `TIME STEP h END t ADAPTIVE '
             'TOLERANCE tol` against fixed steps on six scenes (docs/input.md, TIME; the estimate and the '
             'control in `src/time/step_control.f90`).', '',
             '- Machine: %s, %d cores, Python %s; generated %s.' % (platform.machine(), os.cpu_count(),
                                                                    platform.python_version(),
                                                                    time.strftime('%Y-%m-%d')),
             '- Error: max over the run\'s rows up to END of |x(t) − x_ref(t)| / max |x_ref|, the reference a '
             'fixed step 16 times below the scene\'s, interpolated at the run\'s times. CPU: user + system '
             'seconds of the run (getrusage), outputs HISTORY EVERY 1, no fields.',
             '- "CPU ratio": the adaptive runs\' CPU at the fixed step\'s error (log-log interpolation between '
             'the tolerances that bracket it) over the fixed run\'s; "≤" where every adaptive run is more '
             'accurate (the cheapest of them bounds it).', '',
             '![error against CPU](figures/adaptive_step.png)', '',
             '## Summary', '',
             '| scene | kind | CPU ratio at equal error (over the fixed steps) | issue 36\'s target |',
             '|---|---|---|---|']
    kinds = {'bar_impact': ('wave in contact, then flight', ''),
             'beam_drop_inclined': ('intermittent contact (a drop)', '≤ 1/3'),
             'mass_bounce': ('intermittent contact (bounces)', '≤ 1/3'),
             'ring_impact': ('contact spreading over many nodes, LARGE', ''),
             'block_j2': ('plastic, a load pulse', ''),
             'cantilever_release': ('smooth vibration', '≤ 1.2')}
    for name, rows in results:
        rr = [r['ratio'] for r in rows if 'ratio' in r and np.isfinite(r['ratio'])]
        span = '%.2f … %.2f' % (min(rr), max(rr)) if rr else 'no fixed step\'s error within the adaptive runs\' range'
        kind, target = kinds.get(name, ('', ''))
        lines.append('| %s | %s | %s | %s |' % (name, kind, span, target))
    lines += ['',
              'Reading. Where the motion has quiet phases between events (the bouncing mass: flights at up to '
              '256 STEP, the onsets located on a step\'s end) the adaptive step reaches the fixed steps\' '
              'errors at a small fraction of their CPU. On a smooth vibration it settles on one length, the '
              'fixed step\'s cost. Where contact keeps changing (the ring: every node that closes is an event '
              'after which the step is at most STEP) or a wave runs through a bar, it does not pay: it spends '
              'its steps on the estimate\'s acceleration jumps. S is factorized once per length used (the '
              '"factorizations" column) and kept; each change of length sets the contact\'s Schur columns up '
              'again with the length\'s factor. The inclined '
              'beam\'s clatter is chaotic: errors against its reference are not monotone in h even for fixed '
              'steps, and its ratios are indicative only.', '']
    for (name, rows), sc in zip(results, SCENES):
        lines += ['## %s' % name, '', sc[7] + '; first step %g s.' % sc[3], '',
                  '| run | steps | factorizations of S | h min … max (s) | CPU (s) | error | CPU ratio at equal '
                  'error | balance / E |',
                  '|---|---|---|---|---|---|---|---|']
        for r in rows:
            ratio = ''
            if 'ratio' in r and np.isfinite(r['ratio']):
                ratio = ('≤ ' if r.get('bound') else '') + '%.2f' % r['ratio']
            lines.append('| %s | %d | %d | %.3g … %.3g | %.3f | %.2e | %s | %.1e |' % (
                r['label'], r['steps'], r['nfac'], r['hmin'], r['hmax'], r['cpu'], r['err'], ratio, r['bal']))
        lines.append('')
    with open(args.doc, 'w') as f:
        f.write('\n'.join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--rebond', default=os.path.join(ROOT, 'bin', 'rebond'))
    ap.add_argument('--out', default=os.path.join(ROOT, 'results', 'studies', 'adaptive'))
    ap.add_argument('--doc', default=os.path.join(ROOT, 'docs', 'adaptive-step.md'))
    ap.add_argument('--figures', default=os.path.join(ROOT, 'docs', 'figures'))
    ap.add_argument('--only', default='')
    args = ap.parse_args()
    results = []
    for sc in SCENES:
        if args.only and sc[0] != args.only:
            continue
        rows = study(args, *sc[:7])
        results.append((sc[0], rows))
        for r in rows:
            print('%-20s %-16s steps %7d  cpu %7.3f  err %.2e  ratio %s' % (
                sc[0], r['label'], r['steps'], r['cpu'], r['err'], '%.2f' % r['ratio'] if 'ratio' in r else '-'))
        sys.stdout.flush()
    os.makedirs(args.figures, exist_ok=True)
    plot(results, os.path.join(args.figures, 'adaptive_step.png'))
    if not args.only:
        write_doc(args, results)


if __name__ == '__main__':
    main()
