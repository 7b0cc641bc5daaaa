#!/usr/bin/python3
"""Issue 38's targets at the defaults: a Taylor bar scene (inputs/taylor_plane.dat, the plane-strain
slab, or inputs/taylor_bar.dat, the axisymmetric cylinder) on 4 x 20, 8 x 40 and 16 x 80 meshes at
h = 5e-7, 2.5e-7 and 1.25e-7 s, nothing else changed. For each run: exit code, the time reached,
steps retried as sub-steps, Newton iterations per step (mean, max), |balance| / E, CPU seconds
(user + sys of the child), length and foot half-width (radius) at 80 us, plastic work. Writes a
Markdown table. `make bench` runs both; 16 x 80 takes minutes.

usage: bench_taylor.py [BIN] [OUT] [--scene inputs/taylor_plane.dat] [--meshes 4x20,8x40,16x80]
                       [--steps 5e-7,2.5e-7,1.25e-7]
"""
import argparse
import os
import resource
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NOTES = '<!-- notes: kept by tools/bench_taylor.py -->'


def run(binary, scene, mesh, h, work):
    out = os.path.join(work, 'taylor_%s_%g' % (mesh, h))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([binary, os.path.join(ROOT, scene), '-o', out,
                        '--set', 'RECTANGLE.ELEMENTS=' + mesh.replace('x', ' '), '--set', 'TIME.STEP=%g' % h,
                        '--set', 'OUTPUT.FIELDS=EVERY 0'], capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    row = {'mesh': mesh, 'h': h, 'rc': p.returncode, 'cpu': cpu}
    hist = np.genfromtxt(os.path.join(out, 'history.csv'), delimiter=',', names=True)
    probes = np.genfromtxt(os.path.join(out, 'probes.csv'), delimiter=',', names=True)
    row.update(t=hist['time'][-1], retried=int(np.sum(hist['substeps'] > 1)),
               it_mean=float(np.mean(hist['iterations'][1:])), it_max=int(np.max(hist['iterations'])),
               bal=float(np.max(np.abs(hist['balance'])) / hist['kinetic'][0]), wp=float(hist['dissipated'][-1]))
    names = probes.dtype.names
    ux = [n for n in names if n.endswith('UX')][0]
    uy = [n for n in names if n.endswith('UY')][0]
    row['foot'] = 3.2e-3 + probes[ux][-1]
    # the top's height: the bar spans y = 0.1 to 32.5 mm (ORIGIN 0 0.0001) and its foot ends on the wall
    row['length'] = 32.5e-3 + probes[uy][-1]
    return row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('binary', nargs='?', default=os.path.join(ROOT, 'bin', 'rebond'))
    ap.add_argument('out', nargs='?', default=os.path.join(ROOT, 'docs', 'taylor-defaults.md'))
    ap.add_argument('--scene', default=os.path.join('inputs', 'taylor_plane.dat'))
    ap.add_argument('--meshes', default='4x20,8x40,16x80')
    ap.add_argument('--steps', default='5e-7,2.5e-7,1.25e-7')
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix='rebond-taylor-')
    rows = []
    for mesh in a.meshes.split(','):
        for h in (float(s) for s in a.steps.split(',')):
            r = run(a.binary, a.scene, mesh, h, work)
            rows.append(r)
            print('%s h=%g: exit %d, t %.3g, retried %d, iterations %.2f (max %d), balance %.1e, CPU %.1f s, '
                  'length %.3f mm, foot %.3f mm, plastic work %.1f J' % (
                      mesh, h, r['rc'], r['t'], r['retried'], r['it_mean'], r['it_max'], r['bal'], r['cpu'],
                      1e3 * r['length'], 1e3 * r['foot'], r['wp']), flush=True)
    axi = 'AXISYMMETRIC' in open(os.path.join(ROOT, a.scene)).read()
    foot = 'foot radius' if axi else 'foot half-width'
    lines = ['# Taylor bar at the defaults (issue 38%s)' % (', axisymmetric' if axi else ''), '',
             'Written by `tools/bench_taylor.py` (`make bench`): `%s` with only the mesh' % a.scene,
             '(`RECTANGLE.ELEMENTS`) and the step changed, every other setting the default. Length (the top\'s',
             'height, from y = 32.5 mm) and %s at 80 µs from the probes (top-left UY, bottom-right UX),' % foot,
             'plastic work from history.csv; CPU is user + system time of the run on this machine.', '',
             '| mesh | h (s) | exit | t reached (µs) | retried steps | iterations mean (max) | \\|balance\\|/E | CPU (s) '
             '| length (mm) | %s (mm) | plastic work (J) |' % foot,
             '|---|---|---|---|---|---|---|---|---|---|---|']
    for r in rows:
        lines.append('| %s | %g | %d | %.1f | %d | %.2f (%d) | %.1e | %.1f | %.3f | %.3f | %.1f |' % (
            r['mesh'].replace('x', ' × '), r['h'], r['rc'], 1e6 * r['t'], r['retried'], r['it_mean'], r['it_max'],
            r['bal'], r['cpu'], 1e3 * r['length'], 1e3 * r['foot'], r['wp']))
    # The notes after the table (from the NOTES marker on) are the reader's: kept across runs.
    notes = ''
    if os.path.exists(a.out):
        old = open(a.out).read()
        if NOTES in old:
            notes = '\n' + old[old.index(NOTES):]
    with open(a.out, 'w') as f:
        f.write('\n'.join(lines) + '\n' + notes)
    print('bench_taylor: %s' % a.out)
    return 0 if all(r['rc'] == 0 for r in rows) else 1


if __name__ == '__main__':
    sys.exit(main())
