#!/usr/bin/env python3
"""The nonlinear zone of eq (9)'s iteration, measured (`make zone`, issue 14 item 1).

A 1 m x 0.5 m plane-strain steel block, nx x nx/2 QUAD4, clamped at the bottom, a pw x ph patch of
VON_MISES elements at the top centre (sigma_y 50 MPa, H_ISO 2 GPa) under a 400 MPa pressure
pulse on the patch's top edge (0.1 ms rise, 0.1 ms hold, 0.1 ms release), the rest ELASTIC;
h = 1 us, 400 steps. The mesh is written as a Gmsh 2.2 file (physical groups soft, hard, top,
bottom). Per size: CPU time per step (user + system, OPENBLAS_NUM_THREADS=1; a 2-step run
subtracted, so reading, setup and the S^-1 columns are not in it; best of REPEATS) of
  - the same block all ELASTIC (the linear step: one solve),
  - SCHEME ZONE OFF (every iteration a solve and the whole element loop),
  - SCHEME ZONE ON (the iteration on the patch's equations),
their iterations, the dissipated energy and the balance. Then, on one mesh, the patch grown
until the zone stops paying (where SCHEME ZONE AUTO's limit comes from); and the block turned
over, the patch at its base, thrown at 20 m/s onto a rigid ground (the zone with contact rows).
Writes docs/nonlinear-performance.md between <!-- zone:begin --> and <!-- zone:end -->.

    /usr/bin/python3 tools/zone_study.py [--doc F] [--sizes 76 148 292] [--sweep 148] [--contact 76 148]
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
REBOND = os.environ.get('REBOND_BIN', os.path.join(ROOT, 'bin', 'rebond'))
REPEATS = int(os.environ.get('ZONE_REPEATS', '2'))
NSTEPS = 400


def write_msh(path, nx, ny, pw, ph):
    """Structured nx x ny quads on [0, 1] x [0, 0.5]; elements of the pw x ph patch at the top
    centre in physical group soft, the others in hard; the patch's top edge in top (lines),
    the bottom edge in bottom."""
    i0, j0 = (nx - pw) // 2, ny - ph
    nid = lambda i, j: j * (nx + 1) + i + 1
    lines = ['$MeshFormat', '2.2 0 8', '$EndMeshFormat', '$PhysicalNames', '4',
             '1 1 "top"', '1 2 "bottom"', '2 3 "soft"', '2 4 "hard"', '$EndPhysicalNames',
             '$Nodes', str((nx + 1) * (ny + 1))]
    for j in range(ny + 1):
        for i in range(nx + 1):
            lines.append('%d %.15g %.15g 0' % (nid(i, j), i / nx, 0.5 * j / ny))
    lines.append('$EndNodes')
    els = []
    for i in range(i0, i0 + pw):
        els.append('1 2 1 1 %d %d' % (nid(i, ny), nid(i + 1, ny)))
    for i in range(nx):
        els.append('1 2 2 2 %d %d' % (nid(i, 0), nid(i + 1, 0)))
    for j in range(ny):
        for i in range(nx):
            phys = 3 if (i0 <= i < i0 + pw and j >= j0) else 4
            els.append('3 2 %d %d %d %d %d %d' % (phys, phys, nid(i, j), nid(i + 1, j), nid(i + 1, j + 1),
                                                  nid(i, j + 1)))
    lines += ['$Elements', str(len(els))] + ['%d %s' % (k + 1, e) for k, e in enumerate(els)] + ['$EndElements']
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def write_drop(base, nx, pw, ph):
    """The same block turned over (the patch at the centre of its base, its base edge in
    physical group base) thrown at 20 m/s onto a rigid ground the patch's base nodes touch."""
    write_msh(base + '.msh', nx, nx // 2, pw, ph)
    out, mode = [], None
    for line in open(base + '.msh').read().split('\n'):
        if line in ('$Nodes', '$EndNodes'):
            mode = line
        elif mode == '$Nodes' and len(line.split()) == 4:
            i, x, y, _ = line.split()
            line = '%s %s %.15g 0' % (i, x, 0.5 - float(y))
        out.append(line.replace('"top"', '"base"').replace('"bottom"', '"upper"'))
    with open(base + '.msh', 'w') as f:
        f.write('\n'.join(out))
    with open(base + '.dat', 'w') as f:
        f.write('\n'.join([
            'TITLE "block with a plastic patch at its base, dropped (tools/zone_study.py)"',
            'GMSH m FILE %s' % os.path.basename(base + '.msh'),
            'MATERIAL jm VON_MISES YOUNG 2.1e11 POISSON 0.3 DENSITY 7800 YIELD 5e7 H_ISO 2e9 H_KIN 0',
            'MATERIAL el ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800',
            'SECTION plate THICKNESS 1',
            'MODEL m.soft MATERIAL jm SECTION plate MASS CONSISTENT PLANE STRAIN',
            'MODEL m.hard MATERIAL el SECTION plate MASS CONSISTENT PLANE STRAIN',
            'INITIAL m VELOCITY 0 -20',
            'OBSTACLE ground NODES m.base POINT 0 -1e-5 NORMAL 0 1',
            'TIME STEP 1e-6 END %g' % (NSTEPS * 1e-6),
            'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0', '']))


def write_scene(path, msh, nx, pw, plastic=True):
    """The scene around the mesh: 400 MPa on the patch's top edge (pw/nx m wide)."""
    force = -400e6 * (pw / nx) / (pw + 1)
    law = 'jm' if plastic else 'el'
    text = '\n'.join([
        'TITLE "block with a plastic patch (tools/zone_study.py)"',
        'GMSH m FILE %s' % os.path.basename(msh),
        'MATERIAL jm VON_MISES YOUNG 2.1e11 POISSON 0.3 DENSITY 7800 YIELD 5e7 H_ISO 2e9 H_KIN 0',
        'MATERIAL el ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800',
        'SECTION plate THICKNESS 1',
        'MODEL m.soft MATERIAL %s SECTION plate MASS CONSISTENT PLANE STRAIN' % law,
        'MODEL m.hard MATERIAL el SECTION plate MASS CONSISTENT PLANE STRAIN',
        'FIX m.bottom UX UY',
        'FUNCTION pulse POINTS 0 0  1e-4 1  2e-4 1  3e-4 0',
        'LOAD press NODES m.top FORCE 0 %.9g FUNCTION pulse' % force,
        'TIME STEP 1e-6 END %g' % (NSTEPS * 1e-6),
        'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0', ''])
    with open(path, 'w') as f:
        f.write(text)


def cpu_run(scene, out, sets):
    env = dict(os.environ, OPENBLAS_NUM_THREADS='1')
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([REBOND, scene, '-o', out, '--quiet'] + sum((['--set', s] for s in sets), []),
                       cwd=ROOT, capture_output=True, text=True, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit('zone_study: %s failed: %s' % (scene, p.stderr[-400:]))
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def per_step(scene, work, tag, sets):
    """CPU per step of the time loop (best of REPEATS), and the full run's history."""
    best = float('inf')
    out = os.path.join(work, tag)
    for _ in range(REPEATS):
        short = cpu_run(scene, out + '_short', sets + ['TIME.END=2e-6', 'OUTPUT.HISTORY=0'])
        full = cpu_run(scene, out, sets)
        best = min(best, (full - short) / (NSTEPS - 2))
    h = np.genfromtxt(os.path.join(out, 'history.csv'), delimiter=',', names=True)
    bal = np.max(np.abs(h['balance'])) / np.max(h['kinetic'] + h['internal'])
    return best, int(h['iterations'].sum()), h['dissipated'][-1], bal, h


def zone_line(scene, sets):
    p = subprocess.run([REBOND, scene, '-o', os.path.join(os.path.dirname(scene), 'probe'), '--set', 'TIME.END=1e-6']
                       + sum((['--set', s] for s in sets), []), cwd=ROOT, capture_output=True, text=True)
    for line in p.stdout.splitlines():
        if 'nonlinear zone:' in line:
            return line.split('nonlinear zone:')[1].strip()
    return '?'


def case(work, nx, pw, ph):
    base = os.path.join(work, 'b%d_%d' % (nx, pw))
    write_msh(base + '.msh', nx, nx // 2, pw, ph)
    write_scene(base + '.dat', base + '.msh', nx, pw)
    write_scene(base + '_lin.dat', base + '.msh', nx, pw, plastic=False)
    return base


def fmt_ms(x):
    return '%.2f ms' % (x * 1e3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--doc', default=os.path.join(ROOT, 'docs', 'nonlinear-performance.md'))
    ap.add_argument('--sizes', type=int, nargs='*', default=[76, 148, 292])
    ap.add_argument('--sweep', type=int, default=148)
    ap.add_argument('--contact', type=int, nargs='*', default=[76, 148])
    a = ap.parse_args()
    size_rows = ['| DOFs | mesh | zone (ZONE ON) | linear step | ZONE OFF step | its | ZONE ON step | its | '
                 'OFF / linear | ON / linear | dissipated OFF, ON (J) | max \\|Δkinetic\\|/E ON−OFF | '
                 'max \\|balance\\|/E OFF, ON |',
                 '|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---|']
    sweep_rows = ['| patch | zone equations | ZONE OFF step | its | ZONE ON step | its | ON / OFF | ZONE AUTO says |',
                  '|---:|---:|---:|---:|---:|---:|---:|---|']
    with tempfile.TemporaryDirectory() as work:
        for nx in a.sizes:
            base = case(work, nx, 4, 2)
            lin = per_step(base + '_lin.dat', work, 'lin%d' % nx, [])
            off = per_step(base + '.dat', work, 'off%d' % nx, ['SCHEME.ZONE=OFF'])
            on = per_step(base + '.dat', work, 'on%d' % nx, ['SCHEME.ZONE=ON'])
            e = np.max(off[4]['kinetic'] + off[4]['internal'])
            dk = np.max(np.abs(off[4]['kinetic'] - on[4]['kinetic'])) / e
            ndof = 2 * (nx + 1) * (nx // 2)
            size_rows.append('| %d | %d × %d | %s | %s | %s | %d | %s | %d | %.2f | %.2f | %.4f, %.4f | %.1e | %.1e, %.1e |' % (
                ndof, nx, nx // 2, zone_line(base + '.dat', ['SCHEME.ZONE=ON']), fmt_ms(lin[0]), fmt_ms(off[0]),
                off[1], fmt_ms(on[0]), on[1], off[0] / lin[0], on[0] / lin[0], off[2], on[2], dk, off[3], on[3]))
            print(size_rows[-1], flush=True)
        nx = a.sweep
        for pw, ph in ((4, 2), (8, 4), (12, 6), (16, 8), (24, 12), (32, 16)):
            if pw >= nx or ph >= nx // 2:
                continue
            base = case(work, nx, pw, ph)
            off = per_step(base + '.dat', work, 'soff%d' % pw, ['SCHEME.ZONE=OFF'])
            on = per_step(base + '.dat', work, 'son%d' % pw, ['SCHEME.ZONE=ON'])
            nz = zone_line(base + '.dat', ['SCHEME.ZONE=ON']).split()[0]
            sweep_rows.append('| %d × %d | %s | %s | %d | %s | %d | %.2f | %s |' % (
                pw, ph, nz, fmt_ms(off[0]), off[1], fmt_ms(on[0]), on[1], on[0] / off[0], zone_line(base + '.dat', [])))
            print(sweep_rows[-1], flush=True)
    contact_rows = ['| DOFs | zone | ZONE OFF, AUTO | its | ZONE OFF, ELASTIC | its | ZONE ON | its | ON / OFF AUTO | '
                    'max \\|Δkinetic\\|/E ON − OFF ELASTIC | max \\|balance\\|/E ON |',
                    '|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|']
    with tempfile.TemporaryDirectory() as work:
        for nx in a.contact:
            base = os.path.join(work, 'drop%d' % nx)
            write_drop(base, nx, 4, 2)
            auto = per_step(base + '.dat', work, 'dauto%d' % nx, ['SCHEME.ZONE=OFF'])
            ela = per_step(base + '.dat', work, 'dela%d' % nx, ['SCHEME.ZONE=OFF', 'SCHEME.ITERATION=ELASTIC'])
            on = per_step(base + '.dat', work, 'don%d' % nx, ['SCHEME.ZONE=ON'])
            e = np.max(ela[4]['kinetic'] + ela[4]['internal'])
            dk = np.max(np.abs(ela[4]['kinetic'] - on[4]['kinetic'])) / e
            contact_rows.append('| %d | %s | %s | %d | %s | %d | %s | %d | %.2f | %.1e | %.1e |' % (
                2 * (nx + 1) * (nx // 2 + 1), zone_line(base + '.dat', []), fmt_ms(auto[0]), auto[1], fmt_ms(ela[0]),
                ela[1], fmt_ms(on[0]), on[1], on[0] / auto[0], dk, on[3]))
            print(contact_rows[-1], flush=True)
    block = '\n'.join([
        '', 'Generated by `make zone` (`tools/zone_study.py`; its docstring has the scene). CPU time per step of',
        'the time loop, one thread (`OPENBLAS_NUM_THREADS=1`), best of %d; *its*: iterations of eq (9) over' % REPEATS,
        'the %d steps (ITERATION AUTO, the default). Commands per run:' % NSTEPS, '',
        '    bin/rebond SCENE --set SCHEME.ZONE=OFF|ON        # and the all-ELASTIC block for the linear step', '',
        '### The patch block at three sizes', ''] + size_rows + [
        '', '### The patch grown, %d × %d mesh (%d DOFs)' % (nx, nx // 2, 2 * (nx + 1) * (nx // 2)), ''] + sweep_rows + [
        '', '### With contact rows: the block turned over and thrown onto the ground (patch at its base)', '',
        'Its 5 base nodes under the patch touch the ground (IMPACT AUTO = MASSLESS); the zone iterates with S',
        '(the multipliers are solved with it), so it is compared with the whole system\'s ITERATION ELASTIC',
        '(the same iterates) and timed against the default AUTO.', ''] + contact_rows + [''])
    replace_block(a.doc, '<!-- zone:begin -->', '<!-- zone:end -->', block)


if __name__ == '__main__':
    main()
