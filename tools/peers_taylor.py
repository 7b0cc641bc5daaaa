#!/usr/bin/python3
"""rebond and CalculiX side by side on the copper Taylor bar (`make peers`; issues 32 and 38).

The bar of inputs/taylor_bar.dat (axisymmetric cylinder) and inputs/taylor_plane.dat (plane-strain
half slab, thickness 1 m): 32.4 mm long, 3.2 mm (half-)width, 227 m/s, E 117 GPa, nu 0.35, rho 8930,
J2 with yield 400 MPa and linear isotropic hardening 100 MPa, large strains.

The model both codes run: the foot held on the wall from t = 0 (UY = 0 on the bottom nodes, UX
free: a frictionless wall the foot never leaves), the rest of the bar at -227 m/s, UX = 0 on the
axis (the symmetry plane of the slab). CalculiX 2.20's node-to-surface penalty contact diverges at
this impact ('too many cutbacks' in the first microsecond at every mesh and step tried) and its
surface-to-surface contact cuts the first increment below the minimum, so the wall is modelled
as held in both codes; rebond's own run with its OBSTACLE (0.1 mm gap, IMPACT AUTO) is listed
beside it, the same physics. The rebond scene: the shipped one with `ORIGIN 0 0`, the OBSTACLE
replaced by `FIX bar.bottom UY` (the support wins over the INITIAL velocity: docs/input.md), every
other setting the default (FORMULATION AUTO -> BBAR, ITERATION AUTO, SUBSTEPS AUTO, TOLERANCE).

- CalculiX: CAX4 / CPE4 on the same grid (expanded by ccx into C3D8: full integration, no mean
  dilatation) and CAX4R / CPE4R (C3D8R, reduced integration with hourglass control), *PLASTIC
  (400 MPa at 0, linear to 1.4 GPa at a plastic strain of 10), NLGEOM, *DYNAMIC ALPHA=0 (the
  trapezoidal rule) with automatic incrementation capped at h. A dummy node surface on the whole
  bar: without it ccx 2.20 does not carry *INITIAL CONDITIONS TYPE=VELOCITY to the expanded nodes
  and nothing moves (CalculiX issue #63).
- Measured per run at 80 us: the length (the top's height), the foot radius / half-width (the
  bottom-right node), the internal energy (elastic + plastic) as a fraction of the initial kinetic
  energy, the energy error max |E(t) - E0| / E0 (CalculiX: kinetic + internal energy of *EL PRINT
  ELSE, ELKE every few increments), increments, CPU (user + system of the child). The reference:
  rebond on 16 x 80 at 1.25e-7 s (the finest of docs/taylor-defaults.md); each run's error in
  length and foot is against it, so the table answers 'equal or better accuracy, at what CPU'.

    /usr/bin/python3 tools/peers_taylor.py [--doc docs/peers.md] [--meshes 4x20,8x40] [--steps 5e-7,2.5e-7]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

from peers import ccx_results, cpu_of

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REBOND = os.environ.get('REBOND_BIN', os.path.join(ROOT, 'bin', 'rebond'))
SCENES = {'axi': 'inputs/taylor_bar.dat', 'plane': 'inputs/taylor_plane.dat'}
R, L, V0, TEND = 3.2e-3, 32.4e-3, -227.0, 8e-5
BEGIN, END = '<!-- taylor:begin -->', '<!-- taylor:end -->'
# one thread for both codes (ccx: 'Using up to 1 cpu(s)'; rebond's BLAS would otherwise take the two cores)
ENV = dict(os.environ, OMP_NUM_THREADS='1', OPENBLAS_NUM_THREADS='1', CCX_NPROC_STIFFNESS='1',
           CCX_NPROC_EQUATION_SOLVER='1')


def held_scene(geom, work):
    """The shipped scene with the foot held on the wall from t = 0 instead of the OBSTACLE."""
    text = open(os.path.join(ROOT, SCENES[geom])).read()
    if 'ORIGIN 0 0.0001' not in text or not re.search(r'^OBSTACLE .*$', text, re.M):
        sys.exit('peers_taylor: %s no longer has the expected RECTANGLE ORIGIN and OBSTACLE' % SCENES[geom])
    text = text.replace('ORIGIN 0 0.0001', 'ORIGIN 0 0')
    text = re.sub(r'^OBSTACLE .*$', 'FIX       bar.bottom UY', text, flags=re.M)
    path = os.path.join(work, 'taylor_%s_held.dat' % geom)
    with open(path, 'w') as f:
        f.write(text)
    return path


def run_rebond(geom, nx, ny, h, work, held=True):
    scene = held_scene(geom, work) if held else os.path.join(ROOT, SCENES[geom])
    out = os.path.join(work, 'rebond_%s_%dx%d_%g_%d' % (geom, nx, ny, h, held))
    cmd = [REBOND, scene, '-o', out, '--quiet', '--set', 'RECTANGLE.ELEMENTS=%d %d' % (nx, ny),
           '--set', 'TIME.STEP=%g' % h, '--set', 'OUTPUT.FIELDS=EVERY 0']
    p, cpu = cpu_of(lambda: subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, env=ENV))
    row = dict(ok=False, cpu=cpu)
    if p.returncode != 0 or not os.path.exists(os.path.join(out, 'probes.csv')):
        return row
    hist = np.genfromtxt(os.path.join(out, 'history.csv'), delimiter=',', names=True)
    probes = np.genfromtxt(os.path.join(out, 'probes.csv'), delimiter=',', names=True)
    ux = [n for n in probes.dtype.names if n.endswith('UX')][0]
    uy = [n for n in probes.dtype.names if n.endswith('UY')][0]
    e0 = hist['kinetic'][0] + hist['internal'][0]
    y0 = 0.0 if held else 1e-4
    row.update(ok=abs(hist['time'][-1] - TEND) < 1e-12, steps=len(hist) - 1,
               energy=float(np.max(np.abs(hist['balance'])) / e0), its=float(np.mean(hist['iterations'][1:])),
               length=y0 + L + probes[uy][-1], foot=R + probes[ux][-1], internal=hist['internal'][-1] / e0)
    return row


def ccx_input(geom, nx, ny, h, etype, path, nprint):
    """The held bar as 3D solids on the nx x ny grid: the slab one layer of bricks (UZ = 0 everywhere: plane
    strain), the cylinder a 2-degree sector of bricks (wedges on the axis) whose two side planes keep no
    hoop displacement (a cylindrical *TRANSFORM). Nodes (i, j, k): i radial, j axial, k the layer or side."""
    sector = np.radians(2.0)
    def nid(i, j, k):
        return 1 + k * (nx + 1) * (ny + 1) + j * (nx + 1) + i
    out = ['*HEADING', 'Taylor bar (%s), foot held' % geom, '*NODE']
    for k in range(2):
        for j in range(ny + 1):
            for i in range(nx + 1):
                r, y = R * i / nx, L * j / ny
                if geom == 'plane':
                    x, z = r, 1.0 * k
                else:
                    phi = (k - 0.5) * sector
                    x, z = r * np.cos(phi), r * np.sin(phi)
                if geom == 'axi' and i == 0 and k == 1:
                    continue  # the axis: one node for both sides
                out.append('%d, %.15g, %.15g, %.15g' % (nid(i, j, k), x, y, -z))
    def node(i, j, k):
        return nid(i, j, 0) if geom == 'axi' and i == 0 else nid(i, j, k)
    bricks, wedges = [], []
    for j in range(ny):
        for i in range(nx):
            b = [node(i, j, 0), node(i + 1, j, 0), node(i + 1, j, 1), node(i, j, 1),
                 node(i, j + 1, 0), node(i + 1, j + 1, 0), node(i + 1, j + 1, 1), node(i, j + 1, 1)]
            if geom == 'axi' and i == 0:
                wedges.append([b[0], b[1], b[2], b[4], b[5], b[6]])
            else:
                bricks.append(b)
    k = 0
    out.append('*ELEMENT, TYPE=%s, ELSET=BAR' % etype)
    for b in bricks:
        k += 1
        out.append('%d, %s' % (k, ', '.join(map(str, b))))
    if wedges:
        out.append('*ELEMENT, TYPE=C3D6, ELSET=BAR')
        for w in wedges:
            k += 1
            out.append('%d, %s' % (k, ', '.join(map(str, w))))
    present = [n for n in range(1, nid(nx, ny, 1) + 1) if not (geom == 'axi' and (n - 1) // ((nx + 1) * (ny + 1)) == 1
                                                               and (n - 1) % (nx + 1) == 0)]
    foot = [n for n in present if ((n - 1) % ((nx + 1) * (ny + 1))) // (nx + 1) == 0]
    moving = [n for n in present if n not in foot]
    out += ['*NSET, NSET=NBAR'] + [', '.join(map(str, present[i:i + 12])) for i in range(0, len(present), 12)]
    out += ['*NSET, NSET=NFOOT'] + [', '.join(map(str, foot[i:i + 12])) for i in range(0, len(foot), 12)]
    out += ['*NSET, NSET=NPROBE', '%d, %d' % (nid(nx, 0, 0), nid(0, ny, 0)),
            '*MATERIAL, NAME=CU', '*ELASTIC', '117e9, 0.35', '*DENSITY', '8930',
            '*PLASTIC', '400e6, 0', '1.4e9, 10',
            '*SOLID SECTION, ELSET=BAR, MATERIAL=CU', '*BOUNDARY', 'NFOOT, 2, 2']
    if geom == 'plane':
        out += ['NBAR, 3, 3'] + ['%d, 1, 1' % nid(0, j, k) for k in range(2) for j in range(ny + 1)]
    else:
        axis = [nid(0, j, 0) for j in range(ny + 1)]
        out += ['%d, 1, 1' % n for n in axis] + ['%d, 3, 3' % n for n in axis]
        # each side plane in its own rectangular system: x radial, y the axis, z normal to the plane (no hoop
        # displacement); DOF 2 stays the global axial one, so the foot's and the velocity's DOF are unchanged
        for k in range(2):
            side = [n for n in present if n not in axis and (n - 1) // ((nx + 1) * (ny + 1)) == k]
            phi = (k - 0.5) * sector
            out += ['*NSET, NSET=NSIDE%d' % k] + [', '.join(map(str, side[i:i + 12])) for i in range(0, len(side), 12)]
            out += ['*TRANSFORM, NSET=NSIDE%d, TYPE=R' % k, '%.15g, 0, %.15g, 0, 1, 0' % (np.cos(phi), -np.sin(phi)),
                    '*BOUNDARY', 'NSIDE%d, 3, 3' % k]
    out += ['*INITIAL CONDITIONS, TYPE=VELOCITY'] + ['%d, 2, %g' % (n, V0) for n in moving]
    out += ['*STEP, NLGEOM, INC=10000000', '*DYNAMIC, ALPHA=0', '%g, %g, %g, %g' % (h, TEND, h * 1e-4, h),
            '*NODE PRINT, NSET=NPROBE, FREQUENCY=%d' % nprint, 'U',
            '*EL PRINT, ELSET=BAR, FREQUENCY=%d' % nprint, 'ELSE, ELKE', '*END STEP']
    with open(path, 'w') as f:
        f.write('\n'.join(out) + '\n')
    return nid(nx, 0, 0), nid(0, ny, 0)


def run_ccx(geom, nx, ny, h, work, etype):
    job = os.path.join(work, 'ccx_%s_%dx%d_%g_%s' % (geom, nx, ny, h, etype))
    foot, top = ccx_input(geom, nx, ny, h, etype, job + ".inp", 1)
    p, cpu = cpu_of(lambda: subprocess.run(['ccx', '-i', os.path.basename(job)], cwd=work,
                                           capture_output=True, text=True, env=ENV))
    row = dict(ok=False, cpu=cpu)
    if not os.path.exists(job + '.dat'):
        return row
    d = ccx_results(job + '.dat')
    times = sorted(t for (k, t) in d if k == 'kinetic energy')
    if not times:
        return row
    e = np.array([sum(v[-1] for v in d[('internal energy', t)].values()) +
                  sum(v[-1] for v in d[('kinetic energy', t)].values()) for t in times])
    # E0: the kinetic energy of the moving nodes at t = 0 is not printed; the first print is at t = h on
    # the step's trapezoid, where the energy is still that of the start to the scheme's accuracy
    e0 = e[0]
    inc = len(re.findall(r'^ increment \d+ attempt 1', p.stdout, re.M))
    t = times[-1]
    u = d[('displacements', t)]
    row.update(ok=p.returncode == 0 and abs(t - TEND) < 1e-12, steps=inc, energy=float(np.max(np.abs(e - e0)) / e0),
               its=float('nan'), length=L + u[top][1], foot=R + u[foot][0],
               internal=sum(v[-1] for v in d[('internal energy', t)].values()) / e0, t=t)
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--doc', default=os.path.join(ROOT, 'docs', 'peers.md'))
    ap.add_argument('--geoms', default='axi,plane')
    ap.add_argument('--meshes', default='4x20,8x40')
    ap.add_argument('--steps', default='5e-7,2.5e-7')
    ap.add_argument('--ccx-meshes', default='16x80', help='CalculiX alone on these finer meshes (C3D8, h = the last step)')
    ap.add_argument('--elements', default='C3D8,C3D8R,C3D8I')
    ap.add_argument('--reference', default='16x80:1.25e-7')
    a = ap.parse_args()
    if not shutil.which('ccx'):
        sys.exit('peers_taylor: CalculiX (ccx) not found: apt-get install calculix-ccx (make peers does)')
    if not os.access(REBOND, os.X_OK):
        sys.exit('peers_taylor: bin/rebond not found (make first)')
    mesh = lambda m: tuple(int(x) for x in m.split('x'))
    steps = [float(x) for x in a.steps.split(',')]
    rows, t0 = [], time.time()
    with tempfile.TemporaryDirectory() as work:
        for geom in a.geoms.split(','):
            rm, rh = a.reference.split(':')
            add(rows, geom, 'rebond (reference)', mesh(rm), float(rh), lambda nx, ny, h: run_rebond(geom, nx, ny, h, work))
            for m in a.meshes.split(','):
                for h in steps:
                    add(rows, geom, 'rebond', mesh(m), h, lambda nx, ny, h: run_rebond(geom, nx, ny, h, work))
                    add(rows, geom, 'rebond, OBSTACLE', mesh(m), h,
                        lambda nx, ny, h: run_rebond(geom, nx, ny, h, work, held=False))
                    for et in a.elements.split(','):
                        add(rows, geom, 'CalculiX ' + et, mesh(m), h, lambda nx, ny, h: run_ccx(geom, nx, ny, h, work, et))
            for m in a.ccx_meshes.split(',') if a.ccx_meshes else []:
                add(rows, geom, 'CalculiX C3D8', mesh(m), steps[-1], lambda nx, ny, h: run_ccx(geom, nx, ny, h, work, 'C3D8'))
    write_doc(a.doc, rows, time.time() - t0)


def add(rows, geom, code, m, h, fn):
    r = fn(m[0], m[1], h)
    r.update(geom=geom, code=code, nx=m[0], ny=m[1], h=h)
    rows.append(r)
    print(geom, code, '%dx%d' % m, h, {k: r.get(k) for k in ('ok', 'energy', 'length', 'foot', 'internal', 'cpu', 'steps')},
          flush=True)


def write_doc(doc, rows, wall):
    out = [BEGIN, '## The Taylor bar (issues 32 and 38)', '',
           'Generated by `make peers` (`tools/peers_taylor.py`, %.0f s of runs) on %s: the models, the settings and '
           'what is measured are in its header. The foot is held on the wall from t = 0 in both codes (CalculiX\'s '
           'contact does not run this impact); *rebond, OBSTACLE* is the shipped scene with its wall, for comparison. '
           'Errors are against rebond\'s reference run (16 × 80, the finest step); *E error* = max |E(t) − E0| / E0 '
           '(rebond: max |balance| / E0); *internal* = (elastic + plastic energy) / E0 at 80 µs; CPU = user + system.'
           % (wall, time.strftime('%Y-%m-%d')), '']
    for geom in ('axi', 'plane'):
        sel = [r for r in rows if r['geom'] == geom]
        if not sel:
            continue
        ref = [r for r in sel if r['code'] == 'rebond (reference)' and r['ok']]
        ref = ref[0] if ref else None
        foot = 'foot radius' if geom == 'axi' else 'foot half-width'
        out += ['### %s' % ('Axisymmetric cylinder (inputs/taylor_bar.dat)' if geom == 'axi'
                            else 'Plane-strain slab (inputs/taylor_plane.dat)'), '',
                '| code | mesh | h (s) | outcome | increments | E error | length (mm) | error | %s (mm) | error | '
                'internal | CPU (s) |' % foot, '|---|---|---|---|---|---|---|---|---|---|---|---|']
        for r in sel:
            if not r['ok']:
                out.append('| %s | %d × %d | %g | failed%s | | | | | | | | %.1f |' % (
                    r['code'], r['nx'], r['ny'], r['h'], ' at %.2g µs' % (1e6 * r['t']) if r.get('t') else '', r['cpu']))
                continue
            el = '%+.1f %%' % (100 * (r['length'] / ref['length'] - 1)) if ref else ''
            ef = '%+.1f %%' % (100 * (r['foot'] / ref['foot'] - 1)) if ref else ''
            out.append('| %s | %d × %d | %g | ok | %d | %.1e | %.3f | %s | %.3f | %s | %.4f | %.1f |' % (
                r['code'], r['nx'], r['ny'], r['h'], r['steps'], r['energy'], 1e3 * r['length'], el, 1e3 * r['foot'], ef,
                r['internal'], r['cpu']))
        out += [''] + reading(sel, ref, foot) + ['']
    out.append(END)
    text = open(doc).read() if os.path.exists(doc) else ''
    if BEGIN in text and END in text:
        text = text[:text.index(BEGIN)] + '\n'.join(out) + text[text.index(END) + len(END):]
    else:
        text = text.rstrip('\n') + '\n\n' + '\n'.join(out) + '\n'
    with open(doc, 'w') as f:
        f.write(text)
    print('wrote', doc)


def reading(sel, ref, foot):
    """For each CalculiX run that finished: the cheapest rebond run (the same held model) at equal or better
    accuracy on both the length and the foot (errors against the reference), and the CPU ratio."""
    if ref is None:
        return []
    err = lambda r: (abs(r['length'] / ref['length'] - 1), abs(r['foot'] / ref['foot'] - 1))
    rb = [r for r in sel if r['ok'] and r['code'] == 'rebond']
    out, ratios = ['**Reading** (CPU at equal or better accuracy on the length and the %s):' % foot, ''], []
    for c in [r for r in sel if r['ok'] and r['code'].startswith('CalculiX')]:
        ec = err(c)
        good = [r for r in rb if err(r)[0] <= ec[0] and err(r)[1] <= ec[1]]
        if not good:
            out.append('- %s %d × %d, h = %g (%.1f s; errors %.1f %%, %.1f %%): no rebond run of the table is as accurate '
                       'on both' % (c['code'], c['nx'], c['ny'], c['h'], c['cpu'], 100 * ec[0], 100 * ec[1]))
            continue
        b = min(good, key=lambda r: r['cpu'])
        ratios.append(c['cpu'] / b['cpu'])
        same = [r for r in rb if (r['nx'], r['ny'], r['h']) == (c['nx'], c['ny'], c['h'])]
        out.append('- %s %d × %d, h = %g: %.1f s for errors %.1f %% (length), %.1f %% (%s); rebond %d × %d, h = %g: '
                   '%.1f s for %.1f %%, %.1f %%: **%.0f×** less CPU%s' % (
                       c['code'], c['nx'], c['ny'], c['h'], c['cpu'], 100 * ec[0], 100 * ec[1], foot, b['nx'], b['ny'],
                       b['h'], b['cpu'], 100 * err(b)[0], 100 * err(b)[1], ratios[-1],
                       ' (on the same mesh and step: %.1f×, at %.1f %%, %.1f %%)' % (
                           c['cpu'] / same[0]['cpu'], 100 * err(same[0])[0], 100 * err(same[0])[1]) if same else ''))
    failed = [r for r in sel if not r['ok'] and r['code'].startswith('CalculiX')]
    if failed:
        out.append('- CalculiX failed on %d of its %d runs (%s): no increment it could converge within its cutbacks.'
                   % (len(failed), len(failed) + len(ratios), ', '.join(sorted(set(r['code'].split()[-1]
                                                                                   for r in failed)))))
    if ratios:
        out.append('- rebond at equal or better accuracy: %.0f× to %.0f× less CPU than CalculiX (issue 38 asks 30×).'
                   % (min(ratios), max(ratios)))
    return out


if __name__ == '__main__':
    main()
