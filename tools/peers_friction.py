#!/usr/bin/python3
"""rebond and CalculiX side by side on an oblique frictional impact (issue 33, `make peers`).

An elastic ring (r 0.08-0.1 m, thickness 0.01 m, E 1e7 Pa, nu 0.3, rho 1000 kg/m3; the structured
mesh of tools/ring_mesh.py 12 3: 48 x 3 quads, inputs/ring.msh) hits a rigid wall 0.1 mm below it
at 2 m/s normal speed and 1, 2 or 7 m/s along the wall, with Coulomb friction mu = 0.3 and without.
Measured after 30 ms (the ring has left the wall): the centre's velocity, the rebound angle from
the normal, the spin about the centre (the angular momentum about the centre of mass over its
polar moment, nodal masses lumped from the quads' areas), the energy lost, rebond's balance
error, the increments, the CPU (user + system of the run).

- rebond: inputs/ring_rough_wall.dat (QUAD4 plane stress, KINEMATICS LARGE, rebond's
  defaults: IMPACT AUTO, h = 2e-5 s), FRICTION 0.3 and 0.
- CalculiX 2.20 (Debian calculix-ccx): the same mesh as one layer of C3D8 bricks through the
  thickness (a thin slab: plane stress), NLGEOM, the wall a fixed brick, surface-to-surface penalty
  contact of the outer faces (PRESSURE-OVERCLOSURE=LINEAR, slope E / dx; node-to-surface stopped
  at 8 ms on 'too many cutbacks'), *FRICTION mu with a stick slope E / dx, *DYNAMIC ALPHA=0 (the
  trapezoidal rule) with automatic incrementation from 2e-5 s;
  nodal velocities and positions from *NODE PRINT, energies from *EL PRINT ELSE, ELKE.

Writes docs/peers-friction.md.
    /usr/bin/python3 tools/peers_friction.py [--doc docs/peers-friction.md]
"""
import argparse
import datetime
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peers import ccx_job, cpu_of  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REBOND = os.environ.get('REBOND_BIN', os.path.join(ROOT, 'bin', 'rebond'))
SCENE = 'inputs/ring_rough_wall.dat'
R_IN, R_OUT, THICK, NQ, NW = 0.08, 0.1, 0.01, 12, 3
E, NU, RHO, MU, VN, TEND, H = 1e7, 0.3, 1000.0, 0.3, 2.0, 0.03, 2e-5
WALL = -0.1001


def ring_nodes():
    nt = 4 * NQ
    xy = []
    for j in range(NW + 1):
        r = R_IN + (R_OUT - R_IN) * j / NW
        for i in range(nt):
            a = 2.0 * math.pi * i / nt
            xy.append((r * math.cos(a), r * math.sin(a)))
    quads = []
    for j in range(NW):
        for i in range(nt):
            i2 = (i + 1) % nt
            quads.append((j * nt + i, j * nt + i2, (j + 1) * nt + i2, (j + 1) * nt + i))
    return np.array(xy), quads, [NW * nt + i for i in range(nt)]


def ccx_input(vt, mu, path):
    xy, quads, outer = ring_nodes()
    nn = len(xy)
    dx = 2.0 * math.pi * R_OUT / (4 * NQ)
    out = ['*HEADING', 'ring on a rough wall', '*NODE']
    for k in range(2):
        for i, (x, y) in enumerate(xy):
            out.append('%d, %.12g, %.12g, %.12g' % (1 + i + k * nn, x, y, THICK * k))
    w0 = 2 * nn + 1
    wall = []
    for k in range(2):
        for j in range(2):
            for i in range(2):
                wall.append(w0 + len(wall))
                out.append('%d, %.12g, %.12g, %.12g' % (wall[-1], -0.3 + 0.6 * i, WALL - 0.02 + 0.02 * j,
                                                         -0.01 + 0.03 * k))
    out.append('*ELEMENT, TYPE=C3D8, ELSET=RING')
    for e, q in enumerate(quads):                   # (ring_mesh's quads turn clockwise: reversed)
        q = (q[0], q[3], q[2], q[1])
        out.append('%d, %s' % (e + 1, ', '.join(str(1 + a) for a in q) + ', ' + ', '.join(str(1 + a + nn) for a in q)))
    ew = len(quads) + 1
    b = wall
    out.append('*ELEMENT, TYPE=C3D8, ELSET=WALL')
    out.append('%d, %d, %d, %d, %d, %d, %d, %d, %d' % (ew, b[0], b[1], b[3], b[2], b[4], b[5], b[7], b[6]))
    out += ['*NSET, NSET=NRING, GENERATE', '1, %d, 1' % (2 * nn), '*NSET, NSET=NWALL, GENERATE', '%d, %d, 1' % (w0, w0 + 7),
            '*NSET, NSET=NOUTER']
    out += ['%d, %d' % (1 + a, 1 + a + nn) for a in outer]
    out += ['*MATERIAL, NAME=RUBBER', '*ELASTIC', '%g, %g' % (E, NU), '*DENSITY', '%g' % RHO,
            '*MATERIAL, NAME=STIFF', '*ELASTIC', '%g, 0.3' % (1e4 * E), '*DENSITY', '%g' % RHO,
            '*SOLID SECTION, ELSET=RING, MATERIAL=RUBBER', '*SOLID SECTION, ELSET=WALL, MATERIAL=STIFF',
            '*SURFACE, NAME=SLAVE']
    nt = 4 * NQ
    out += ['%d, S4' % ((NW - 1) * nt + i + 1) for i in range(nt)]       # (the outer faces of the outer layer)
    out += ['*SURFACE, NAME=MASTER', '%d, S5' % ew,                         # (the wall's top face, y+)
            '*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE', 'SLAVE, MASTER',
            '*SURFACE INTERACTION, NAME=SI', '*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR', '%g' % (E / dx)]
    if mu > 0.0:
        out += ['*FRICTION', '%g, %g' % (mu, E / dx)]
    out += ['*BOUNDARY', 'NWALL, 1, 3', '*INITIAL CONDITIONS, TYPE=VELOCITY']
    out += ['NRING, 1, %g' % vt, 'NRING, 2, %g' % (-VN)]
    out += ['*STEP, NLGEOM, INC=10000000', '*DYNAMIC, ALPHA=0', '%g, %g, %g, %g' % (H, TEND, H * 1e-4, H),
            '*NODE PRINT, NSET=NRING, FREQUENCY=10000000', 'V, U', '*EL PRINT, ELSET=RING, FREQUENCY=10000000',
            'ELSE, ELKE', '*END STEP']
    with open(path, 'w') as f:
        f.write('\n'.join(out) + '\n')


def rigid_motion(x, v, w):
    """Centre velocity and spin of nodes at x with velocities v and mass weights w (sum 1)."""
    xc = w @ x
    vc = w @ v
    d = x - xc
    dv = v - vc
    lz = np.sum(w * (d[:, 0] * dv[:, 1] - d[:, 1] * dv[:, 0]))
    iz = np.sum(w * (d[:, 0] ** 2 + d[:, 1] ** 2))
    return vc, lz / iz


def lumped_weights(xy, quads):
    w = np.zeros(len(xy))
    for q in quads:
        p = xy[list(q)]
        area = 0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))
        w[list(q)] += area / 4.0
    return w / w.sum()


def run_ccx(vt, mu, work):
    job = os.path.join(work, 'ring_%g_%g' % (vt, mu))
    ccx_input(vt, mu, job + '.inp')
    p, cpu, d = ccx_job(job)
    if d is None:
        return dict(ok=False, cpu=cpu)
    times = sorted(t for (k, t) in d if k == 'velocities')
    if not times or abs(times[-1] - TEND) > 1e-9:
        return dict(ok=False, cpu=cpu)
    xy, quads, _ = ring_nodes()
    nn = len(xy)
    t = times[-1]
    vel = np.array([d[('velocities', t)][i + 1][:2] for i in range(nn)])
    dis = np.array([d[('displacements', t)][i + 1][:2] for i in range(nn)])
    vc, w = rigid_motion(xy + dis, vel, lumped_weights(xy, quads))
    e0 = 0.5 * RHO * math.pi * (R_OUT ** 2 - R_IN ** 2) * THICK * (vt * vt + VN * VN)
    e = sum(v[-1] for v in d[('internal energy', t)].values()) + sum(v[-1] for v in d[('kinetic energy', t)].values())
    steps = sum(1 for line in open(job + '.sta') if re.match(r'\s+1\s+\d+\s+\d+\s', line))
    return dict(ok=p.returncode == 0, cpu=cpu, vc=vc, w=w, lost=(e0 - e) / e0, balance=None, steps=steps)


def run_rebond(vt, mu, work):
    """The scene on tools/ring_mesh.py's mesh (the node order of ring_nodes) in the work folder."""
    mesh = os.path.join(work, 'ring12.msh')
    if not os.path.exists(mesh):
        subprocess.run(['/usr/bin/python3', os.path.join(ROOT, 'tools', 'ring_mesh.py'), str(NQ), str(NW), mesh], check=True)
    with open(os.path.join(ROOT, SCENE)) as f:
        text = re.sub(r'FILE \S+', 'FILE ring12.msh', f.read())
    scene = os.path.join(work, 'ring_oblique.dat')
    with open(scene, 'w') as f:
        f.write(text)
    out = os.path.join(work, 'rebond_%g_%g' % (vt, mu))
    cmd = [REBOND, scene, '-o', out, '--quiet', '--set', 'INITIAL.VELOCITY=%r %r' % (vt, -VN), '--set',
           'OBSTACLE.FRICTION=%r' % mu, '--set', 'OUTPUT.FIELDS=100000']
    p, cpu = cpu_of(lambda: subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True))
    if p.returncode != 0:
        return dict(ok=False, cpu=cpu)
    import h5py
    xy, quads, _ = ring_nodes()
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        last = sorted(k for k in f.keys() if k.startswith('step_'))[-1]
        u = np.array(f[last]['displacement'])[:, :2]
        v = np.array(f[last]['velocity'])[:, :2]
    hist = np.genfromtxt(os.path.join(out, 'history.csv'), delimiter=',', names=True)
    vc, w = rigid_motion(xy + u, v, lumped_weights(xy, quads))
    e0 = hist['kinetic'][0] + hist['internal'][0]
    lost = (e0 - hist['kinetic'][-1] - hist['internal'][-1]) / e0
    return dict(ok=True, cpu=cpu, vc=vc, w=w, lost=lost, balance=np.abs(hist['balance']).max() / e0, steps=len(hist) - 1)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--doc', default=os.path.join(ROOT, 'docs', 'peers-friction.md'))
    args = ap.parse_args()
    if shutil.which('ccx') is None:
        sys.exit('peers_friction: CalculiX (ccx) not found: make peers installs Debian\'s calculix-ccx')
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for vt in [1.0, 2.0, 7.0]:
            for mu in [MU, 0.0]:
                for code, fn in [('rebond', run_rebond), ('CalculiX', run_ccx)]:
                    r = fn(vt, mu, work)
                    rows.append((vt, mu, code, r))
                    if r['ok']:
                        print('%4.1f m/s along, mu %.1f, %-8s: v = (%.4f, %.4f), %.2f deg, spin %.3f rad/s, %.2f %% of E '
                              'lost, %.1f s CPU' % (vt, mu, code, r['vc'][0], r['vc'][1],
                                                    math.degrees(math.atan2(r['vc'][0], r['vc'][1])), r['w'],
                                                    100 * r['lost'], r['cpu']), flush=True)
                    else:
                        print('%4.1f m/s along, mu %.1f, %-8s: failed (%.1f s CPU)' % (vt, mu, code, r['cpu']), flush=True)
    with open(args.doc, 'w') as f:
        f.write('# rebond and CalculiX on an oblique frictional impact (issue 33)\n\n')
        f.write('Generated by `make peers` (`tools/peers_friction.py`) on %s. The models, the settings and what is '
                'measured: the header of `tools/peers_friction.py`.\n\n' % datetime.date.today().isoformat())
        f.write('| along the wall (m/s) | μ | code | rebound v (m/s) | angle from the normal | spin (rad/s) | '
                'energy lost | balance error | increments | CPU (s) |\n|---|---|---|---|---|---|---|---|---|---|\n')
        for vt, mu, code, r in rows:
            if not r['ok']:
                f.write('| %g | %g | %s | failed | | | | | | %.1f |\n' % (vt, mu, code, r['cpu']))
                continue
            bal = '%.1e' % r['balance'] if r['balance'] is not None else '—'
            f.write('| %g | %g | %s | (%.4f, %.4f) | %.2f° | %.3f | %.2f %% | %s | %d | %.2f |\n' %
                    (vt, mu, code, r['vc'][0], r['vc'][1], math.degrees(math.atan2(r['vc'][0], r['vc'][1])), r['w'],
                     100 * r['lost'], bal, r['steps'], r['cpu']))
        f.write('\nEnergy lost: 1 - (kinetic + strain energy at 30 ms) / at t = 0: the friction\'s dissipation, '
                'the penalty\'s error and the wall\'s share in CalculiX; rebond\'s balance error counts what its '
                'history books (friction_dissipated included): what the scheme created or lost.\n')


if __name__ == '__main__':
    main()
