#!/usr/bin/env python3
"""rebond and CalculiX side by side on code_aster SDNV100's bar impact (`make peers`).

The bar: L 0.2 m, section 0.02 x 0.02 m, E 2e11 Pa, nu 0, rho 8000 kg/m3, v0 -100 m/s toward a
rigid wall 2 mm away. Exact: contact from 2e-5 to 1e-4 s (2 L / c, c = 5000 m/s), the bar leaves at
+100 m/s, energy 3200 J kept. The same bar elastic-plastic (YIELD 2.5e8 Pa, linear isotropic
hardening 2e10 Pa: tests/scenes/retry/plastic_bar_wall.dat) has no closed form: energy (kinetic +
strain + plastic work) kept.

- rebond: inputs/sdnv100.dat (N BAR2, rebond's defaults: no MASS, so the mass tuned to the step
  where c h/dx <= 1 and the consistent one above, and IMPACT AUTO) and
  tests/scenes/retry/plastic_bar_wall.dat (consistent mass), `--set LINE.bar.ELEMENTS=N --set TIME.STEP=h`.
- CalculiX 2.20 (Debian calculix-ccx): N C3D8 bricks (one across the section), the wall a fixed
  brick, node-to-surface penalty contact (PRESSURE-OVERCLOSURE=LINEAR, slope E / dx, and one run
  at 10 E / dx: the stiffer penalty takes ~100x the increments and gains more energy), *DYNAMIC
  ALPHA=0 (the trapezoidal rule, Newmark's average acceleration) with automatic incrementation
  from h (fixed increments, *DYNAMIC DIRECT, diverge at the contact: 'solution seems to diverge;
  please try automatic incrementation'), *PLASTIC for the plastic bar. Energies from *EL PRINT
  ELSE, ELKE (internal energy includes the plastic work), velocities from *NODE PRINT.

Measured per run: max |E(t) - E0| / E0, contact start and end (rebond: contacts.csv; CalculiX: the
bar's end face within 1 um of the wall), rebound velocity (the bar's mean velocity at the end,
1.4e-4 s), CPU (user + system of the run). Writes docs/peers.md and docs/figures/peers.png.

    /usr/bin/python3 tools/peers.py [--doc docs/peers.md]
"""
import argparse
import collections
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REBOND = os.environ.get('REBOND_BIN', os.path.join(ROOT, 'bin', 'rebond'))
ELASTIC = 'inputs/sdnv100.dat'
PLASTIC = 'tests/scenes/retry/plastic_bar_wall.dat'
L, A_SIDE, GAP, E, RHO, V0 = 0.2, 0.02, 0.002, 2e11, 8000.0, -100.0
MASS = RHO * A_SIDE ** 2 * L
TEND = 1.4e-4


def cpu_of(fn):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = fn()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return out, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def ccx_input(n, h, plastic, path, factor=1.0):
    """The bar as n C3D8 bricks and the wall as one fixed brick, penalty contact, *DYNAMIC ALPHA=0."""
    dx = L / n
    out = ['*HEADING', 'SDNV100 bar on a wall', '*NODE']

    def node(i, j, k):
        return 1 + i * 4 + j * 2 + k
    for i in range(n + 1):
        for j in range(2):
            for k in range(2):
                out.append('%d, %.12g, %.12g, %.12g' % (node(i, j, k), GAP + dx * i, A_SIDE * j, A_SIDE * k))
    w0 = node(n, 1, 1) + 1

    def wnode(i, j, k):
        return w0 + i * 4 + j * 2 + k
    for i in range(2):
        for j in range(2):
            for k in range(2):
                out.append('%d, %.12g, %.12g, %.12g' % (wnode(i, j, k), -0.01 + 0.01 * i, -0.01 + 0.04 * j,
                                                         -0.01 + 0.04 * k))

    def brick(f):
        return [f(0, 0, 0), f(1, 0, 0), f(1, 1, 0), f(0, 1, 0), f(0, 0, 1), f(1, 0, 1), f(1, 1, 1), f(0, 1, 1)]
    out.append('*ELEMENT, TYPE=C3D8, ELSET=BAR')
    for i in range(n):
        out.append('%d, %s' % (i + 1, ', '.join(map(str, brick(lambda a, b, c: node(i + a, b, c))))))
    out.append('*ELEMENT, TYPE=C3D8, ELSET=WALL')
    out.append('%d, %s' % (n + 1, ', '.join(map(str, brick(wnode)))))
    out += ['*NSET, NSET=NBAR, GENERATE', '1, %d, 1' % node(n, 1, 1),
            '*NSET, NSET=NWALL, GENERATE', '%d, %d, 1' % (w0, w0 + 7),
            '*NSET, NSET=NEND', '1, 2, 3, 4',
            '*MATERIAL, NAME=STEEL', '*ELASTIC', '%g, 0' % E, '*DENSITY', '%g' % RHO]
    if plastic:
        out += ['*PLASTIC', '2.5e8, 0', '%g, 1' % (2.5e8 + 2e10)]
    out += ['*SOLID SECTION, ELSET=BAR, MATERIAL=STEEL', '*SOLID SECTION, ELSET=WALL, MATERIAL=STEEL',
            '*SURFACE, NAME=SLAVE, TYPE=NODE', 'NEND', '*SURFACE, NAME=MASTER', '%d, S4' % (n + 1),
            '*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE', 'SLAVE, MASTER',
            '*SURFACE INTERACTION, NAME=SI', '*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR', '%g' % (factor * E / dx),
            '*BOUNDARY', 'NWALL, 1, 3', '*INITIAL CONDITIONS, TYPE=VELOCITY']
    out += ['%d, 1, %g' % (i, V0) for i in range(1, node(n, 1, 1) + 1)]
    out += ['*STEP, INC=10000000', '*DYNAMIC, ALPHA=0', '%g, %g, %g, %g' % (h, TEND, h * 1e-4, h),
            '*NODE PRINT, NSET=NBAR, FREQUENCY=1', 'V, U', '*EL PRINT, ELSET=BAR, FREQUENCY=1', 'ELSE, ELKE',
            '*END STEP']
    with open(path, 'w') as f:
        f.write('\n'.join(out) + '\n')


def ccx_results(path):
    """{(quantity, time): {id: values}} of a CalculiX .dat file."""
    data = collections.defaultdict(dict)
    cur = None
    with open(path) as f:
        for line in f:
            m = re.match(r'\s*(velocities|displacements|internal energy|kinetic energy).*time\s+(\S+)', line)
            if m:
                cur = (m.group(1), float(m.group(2)))
                continue
            p = line.split()
            if cur and len(p) >= 2:
                try:                    # ('L': values in a node's local system, *TRANSFORM)
                    data[cur][int(p[0])] = [float(x) for x in p[1:] if x != 'L']
                except ValueError:
                    pass
    return data


def ccx_job(job):
    """Run CalculiX on job.inp (in its folder): (process, CPU, results of job.dat or None)."""
    p, cpu = cpu_of(lambda: subprocess.run(['ccx', '-i', os.path.basename(job)], cwd=os.path.dirname(job),
                                           capture_output=True, text=True))
    return p, cpu, ccx_results(job + '.dat') if os.path.exists(job + '.dat') else None


def run_ccx(n, h, plastic, work, factor=1.0):
    job = os.path.join(work, 'ccx_%d_%g_%d_%g' % (n, h, plastic, factor))
    ccx_input(n, h, plastic, job + '.inp', factor)
    p, cpu, d = ccx_job(job)
    if d is None:
        return dict(ok=False, cpu=cpu)
    times = sorted(t for (k, t) in d if k == 'velocities')
    e = np.array([sum(v[-1] for v in d[('internal energy', t)].values()) +
                  sum(v[-1] for v in d[('kinetic energy', t)].values()) for t in times])
    xend = np.array([GAP + d[('displacements', t)][1][0] for t in times])
    vmean = np.array([np.mean([v[0] for v in d[('velocities', t)].values()]) for t in times])
    touching = np.nonzero(xend <= 1e-6)[0]
    ok = p.returncode == 0 and abs(times[-1] - TEND) < 1e-9
    e0 = 0.5 * MASS * V0 ** 2
    return dict(ok=ok, cpu=cpu, steps=len(times), energy=np.max(np.abs(e - e0)) / e0,
                t_on=times[touching[0]] if len(touching) else np.nan,
                t_off=times[touching[-1]] if len(touching) else np.nan, rebound=vmean[-1])


def run_rebond(n, h, plastic, work, factor=None):
    out = os.path.join(work, 'rebond_%d_%g_%d' % (n, h, plastic))
    scene = PLASTIC if plastic else ELASTIC
    sets = ['LINE.bar.ELEMENTS=%d' % n, 'TIME.STEP=%g' % h, 'TIME.END=%g' % TEND, 'OUTPUT.HISTORY=1', 'OUTPUT.FIELDS=0']
    cmd = [REBOND, scene, '-o', out, '--quiet']
    for s in sets:
        cmd += ['--set', s]
    p, cpu = cpu_of(lambda: subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True))
    if p.returncode != 0:
        return dict(ok=False, cpu=cpu)
    hist = np.genfromtxt(os.path.join(out, 'history.csv'), delimiter=',', names=True)
    c = np.genfromtxt(os.path.join(out, 'contacts.csv'), delimiter=',', names=True, dtype=None, encoding=None)
    on = c['time'][c['active'] > 0]
    e0 = hist['kinetic'][0] + hist['internal'][0]
    return dict(ok=True, cpu=cpu, steps=len(hist) - 1, energy=np.max(np.abs(hist['balance'])) / e0,
                t_on=on.min() if len(on) else np.nan, t_off=on.max() if len(on) else np.nan,
                rebound=hist['momentum_x'][-1] / MASS)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--doc', default=os.path.join(ROOT, 'docs', 'peers.md'))
    ap.add_argument('--meshes', nargs='+', type=int, default=[20, 40, 80])
    ap.add_argument('--steps', nargs='+', type=float, default=[4e-6, 2e-6, 1e-6])
    ap.add_argument('--plastic-meshes', nargs='+', type=int, default=[20, 40])
    ap.add_argument('--plastic-steps', nargs='+', type=float, default=[4e-6, 1e-6])
    ap.add_argument('--stiff', type=float, default=10.0,
                    help='one more CalculiX run (elastic, the first mesh and step) with this penalty factor')
    a = ap.parse_args()
    if not shutil.which('ccx'):
        sys.exit('peers: CalculiX (ccx) not found: apt-get install calculix-ccx (make peers does)')
    if not os.access(REBOND, os.X_OK):
        sys.exit('peers: bin/rebond not found (make first)')
    rows = []
    t0 = time.time()
    with tempfile.TemporaryDirectory() as work:
        for plastic, meshes, steps in ((False, a.meshes, a.steps), (True, a.plastic_meshes, a.plastic_steps)):
            for n in meshes:
                for h in steps:
                    for code, fn in (('rebond', run_rebond), ('CalculiX', run_ccx)):
                        add(rows, code, fn, n, h, plastic, work, None if code == 'rebond' else 1.0)
        if a.stiff > 0:
            add(rows, 'CalculiX', run_ccx, a.meshes[0], a.steps[0], False, work, a.stiff)
    write_doc(a.doc, rows, time.time() - t0)


def add(rows, code, fn, n, h, plastic, work, factor):
    r = fn(n, h, plastic, work) if factor is None else fn(n, h, plastic, work, factor)
    r.update(code=code, n=n, h=h, plastic=plastic, factor=factor)
    rows.append(r)
    print(code, 'plastic' if plastic else 'elastic', n, h, factor, {k: r.get(k) for k in
          ('ok', 'energy', 't_on', 't_off', 'rebound', 'cpu', 'steps')}, flush=True)


def write_doc(doc, rows, wall):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    lines = ['# rebond and CalculiX side by side (issue 14, item 6)', '',
             'Generated by `make peers` (`tools/peers.py`, %.0f s of runs) on %s with CalculiX %s. The models, the '
             'settings and what is measured: the header of `tools/peers.py`. Exact for the elastic bar: contact '
             '[2e-5, 1e-4] s, rebound +100 m/s, energy kept. *E error* = max |E(t) − E0| / E0 over the run (rebond: '
             'max |balance| / E0, which includes the plastic work); CPU = user + system of the run.'
             % (wall, time.strftime('%Y-%m-%d'), ccx_version()), '',
             '| bar | code | penalty | elements | h (s) | c h/dx | outcome | increments | E error | contact start (s) '
             '| contact end (s) | rebound (m/s) | CPU (s) |', '|---|---|---|---|---|---|---|---|---|---|---|---|---|']
    for r in rows:
        pen = '—' if r['factor'] is None else '%g E/dx' % r['factor']
        if r['ok']:
            lines.append('| %s | %s | %s | %d | %g | %g | ok | %d | %.1e | %.3e | %.3e | %.3f | %.2f |'
                         % ('plastic' if r['plastic'] else 'elastic', r['code'], pen, r['n'], r['h'], cfl(r), r['steps'],
                            r['energy'], r['t_on'], r['t_off'], r['rebound'], r['cpu']))
        else:
            lines.append('| %s | %s | %s | %d | %g | %g | failed | | | | | | %.2f |'
                         % ('plastic' if r['plastic'] else 'elastic', r['code'], pen, r['n'], r['h'], cfl(r), r['cpu']))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for code, style in (('rebond', 'o'), ('CalculiX', 's')):
        for plastic, colour in ((False, 'tab:blue'), (True, 'tab:red')):
            sel = [r for r in rows if r['code'] == code and r['plastic'] == plastic and r['ok']]
            if not sel:
                continue
            axes[0].loglog([r['cpu'] for r in sel], [max(r['energy'], 1e-16) for r in sel], style, color=colour,
                           label='%s, %s bar' % (code, 'plastic' if plastic else 'elastic'))
            if not plastic:
                axes[1].loglog([r['cpu'] for r in sel], [max(abs(r['rebound'] - 100.0) / 100.0, 1e-6) for r in sel],
                               style, color=colour, label=code)
    axes[0].set_xlabel('CPU s')
    axes[0].set_ylabel('max |E(t) - E0| / E0')
    axes[0].set_title('Energy error against CPU')
    axes[1].set_xlabel('CPU s')
    axes[1].set_ylabel('|rebound - 100| / 100')
    axes[1].set_title('Elastic bar: rebound error against CPU')
    for ax in axes:
        ax.grid(True, which='both', alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, 'docs', 'figures', 'peers.png'), dpi=100)
    lines += ['', '![accuracy against CPU](figures/peers.png)', ''] + reading(rows)
    # tools/peers_taylor.py's section (between its markers) is kept as it is
    kept = ''
    if os.path.exists(doc):
        old = open(doc).read()
        b, e = '<!-- taylor:begin -->', '<!-- taylor:end -->'
        if b in old and e in old:
            kept = old[old.index(b):old.index(e) + len(e)] + '\n'
    with open(doc, 'w') as f:
        f.write('\n'.join(lines) + '\n' + kept)
    print('wrote', doc)


def reading(rows):
    """The measured contrasts, in numbers."""
    out = ['**Reading** (from the rows above):', '']
    for plastic in (False, True):
        rb = [r for r in rows if r['ok'] and r['code'] == 'rebond' and r['plastic'] == plastic]
        cx = [r for r in rows if r['ok'] and r['code'] == 'CalculiX' and r['plastic'] == plastic and r['factor'] == 1.0]
        if not rb or not cx:
            continue
        ratios = []
        for r in rb:
            m = [c for c in cx if c['n'] == r['n'] and c['h'] == r['h']]
            if m:
                ratios.append(m[0]['cpu'] / max(r['cpu'], 1e-3))
        out.append('- %s bar: energy error rebond %.0e … %.0e, CalculiX %.1e … %.1e; CPU CalculiX / rebond at the '
                   'same mesh and step: median %.0f× (%.0f× … %.0f×; rebond\'s runs take hundredths of a second, '
                   'mostly the process start).'
                   % ('elastic' if not plastic else 'elastic-plastic', min(r['energy'] for r in rb),
                      max(r['energy'] for r in rb), min(c['energy'] for c in cx), max(c['energy'] for c in cx),
                      np.median(ratios), min(ratios), max(ratios)))
    stiff = [r for r in rows if r['ok'] and r['code'] == 'CalculiX' and r['factor'] not in (None, 1.0)]
    for s in stiff:
        out.append('- CalculiX with the stiffer penalty %g E/dx (%d elements, h = %g): %d increments, energy error '
                   '%.1e, rebound %.2f m/s, %.0f s CPU: the penalty trades penetration for energy and time.'
                   % (s['factor'], s['n'], s['h'], s['steps'], s['energy'], s['rebound'], s['cpu']))
    for tuned in (True, False):
        rb = [r for r in rows if r['ok'] and r['code'] == 'rebond' and not r['plastic'] and (cfl(r) <= 1) == tuned]
        cx = [r for r in rows if r['ok'] and r['code'] == 'CalculiX' and not r['plastic'] and r['factor'] == 1.0
              and (cfl(r) <= 1) == tuned]
        if rb and cx:
            out.append('- Rebound error (elastic, exact +100 m/s) at c h/dx %s: rebond %s, CalculiX %s%s.'
                       % ('<= 1' if tuned else '> 1', rebound_range(rb), rebound_range(cx),
                          ' (rebond\'s default mass is the one tuned to the step there: docs/contact.md, "The default '
                          'mass")' if tuned else ' (no tuned mass exists: the consistent one; the time scheme loses a '
                          'few % there whatever the mass)'))
    return out + ['']


def cfl(r):
    """c h/dx of a run."""
    return round((E / RHO) ** 0.5 * r['h'] * r['n'] / L, 3)


def rebound_range(rows):
    errs = sorted(abs(r['rebound'] - 100.0) for r in rows)
    return '%.3f … %.3f %%' % (errs[0], errs[-1])


def ccx_version():
    p = subprocess.run(['ccx', '-v'], capture_output=True, text=True)
    m = re.search(r'Version\s+(\S+)', p.stdout + p.stderr)
    return m.group(1) if m else '?'


if __name__ == '__main__':
    main()
