#!/usr/bin/python3
"""A solid rubber ball spinning without translation, set on a rough floor under gravity (issue 33,
`make studies`; docs/friction-sphere.md). The friction speeds its centre up and slows its spin until
the contact point rolls, v = ω r, at the rigid body's
    v_f = ω0 r I / (I + m r²) = 2/7 ω0 r,  t_f = v_f / (μ g),  loss ½ I ω0² m r² / (I + m r²)
(I = 2/5 m r²). TET10 balls from tools/ball_mesh.py (N: 2N cells across a diameter), KINEMATICS
LARGE, the defaults otherwise. Measured: the rolling speed, the end of the slip phase, the friction's
dissipation against the rigid body's, the balance; CPU of each run.

usage: sphere_spin.py [--out DIR] [--doc docs/friction-sphere.md] [--figures docs/figures] [--n 2 3] [--rebond BIN]
"""
import argparse
import os
import resource
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
R, W0, MU, G, RHO, H = 0.1, 20.0, 0.3, 9.81, 1000.0, 2e-4
SCENE = '''TITLE     "A spinning ball set on a rough floor: slip, then rolling"
DIMENSION 3
GMSH      b FILE {mesh}
MATERIAL  rubber ELASTIC YOUNG 1e7 POISSON 0.3 DENSITY {rho}
MODEL     b.ball MATERIAL rubber KINEMATICS LARGE
OBSTACLE  floor NODES b.surface POINT 0 0 0 NORMAL 0 0 1 FRICTION {mu}
GRAVITY   GZ -{g}
INITIAL   b.ball ANGULAR_VELOCITY 0 {w0} 0 ABOUT 0 0 {r}
TIME      STEP {h} END 0.25
OUTPUT    HISTORY EVERY 5  FIELDS EVERY 0
'''


def run_case(rebond, n, out):
    os.makedirs(out, exist_ok=True)
    mesh = os.path.join(out, 'ball%d.msh' % n)
    subprocess.run([sys.executable, os.path.join(ROOT, 'tools', 'ball_mesh.py'), str(n), repr(R), mesh], check=True,
                   capture_output=True)
    scene = os.path.join(out, 'ball%d.dat' % n)
    with open(scene, 'w') as f:
        f.write(SCENE.format(mesh=os.path.basename(mesh), rho=RHO, mu=MU, g=G, w0=W0, r=R, h=H))
    res = os.path.join(out, 'ball%d' % n)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([rebond, scene, '-o', res, '--quiet'], check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    h = np.genfromtxt(os.path.join(res, 'history.csv'), delimiter=',', names=True)
    return h, cpu


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--out', default=os.path.join(ROOT, 'results', 'studies', 'sphere_spin'))
    ap.add_argument('--doc', default=os.path.join(ROOT, 'docs', 'friction-sphere.md'))
    ap.add_argument('--figures', default=os.path.join(ROOT, 'docs', 'figures'))
    ap.add_argument('--n', type=int, nargs='+', default=[2, 3])
    ap.add_argument('--rebond', default=os.path.join(ROOT, 'bin', 'rebond'))
    a = ap.parse_args()
    m = 4.0 / 3.0 * np.pi * R ** 3 * RHO
    inertia = 0.4 * m * R * R
    vf = W0 * R * inertia / (inertia + m * R * R)
    tf = vf / (MU * G)
    loss = 0.5 * inertia * W0 ** 2 * m * R * R / (inertia + m * R * R)
    rows, curves = [], []
    for n in a.n:
        h, cpu = run_case(a.rebond, n, a.out)
        t = h['time']
        v = h['momentum_x'] / m
        fd = h['friction_dissipated']
        v_end = v[t > 0.22].mean()
        t_end = t[np.argmax(fd >= fd[-1] - 1e-3 * loss)]
        bal = np.abs(h['balance']).max() / np.abs(h['kinetic']).max()
        side = np.abs(h['momentum_y']).max() / (m * vf)
        rows.append((n, len(t), v_end, t_end, fd[-1], bal, side, cpu))
        curves.append((n, t, v))
        print('N %d: v_end %.5f (rigid %.5f, %+.2f %%), slip ends %.4f s (rigid %.4f), loss %.5f J (rigid %.5f, %+.2f %%), '
              '|balance|/E %.1e, CPU %.0f s' % (n, v_end, vf, 100 * (v_end / vf - 1), t_end, tf, fd[-1], loss,
                                                100 * (fd[-1] / loss - 1), bal, cpu))
    lines = ['# A ball spinning on a rough floor (issue 33, 3D friction)', '',
             'Written by `tools/sphere_spin.py` (`make studies`). A rubber ball (radius %g m, E 1e7 Pa, ν 0.3, '
             'ρ %g kg/m³, m %.4f kg) spinning at ω0 = %g rad/s about y without translation, set on a floor with '
             'μ = %g under gravity; TET10 balls from `tools/ball_mesh.py` (a cube of (2N)³ cells cut into Kuhn\'s '
             'tetrahedra, mapped onto the ball), KINEMATICS LARGE, h = %g s, the defaults otherwise (IMPACT AUTO). '
             'Rigid body: v_f = 2/7 ω0 r = %.5f m/s at t_f = v_f/(μ g) = %.4f s, friction loss ½ I ω0² m r²/(I + m r²) '
             '= %.5f J.' % (R, RHO, m, W0, MU, H, vf, tf, loss), '',
             '| N | TET10 | rolling speed (m/s) | vs rigid | slip ends (s) | friction loss (J) | vs rigid | '
             '\\|balance\\|/E | max \\|p_y\\| / m v_f | CPU (s) |',
             '|---|---|---|---|---|---|---|---|---|---|']
    for n, _, v_end, t_end, fl, bal, side, cpu in rows:
        lines.append('| %d | %d | %.5f | %+.2f %% | %.4f | %.5f | %+.2f %% | %.1e | %.1e | %.0f |' % (
            n, 48 * n ** 3, v_end, 100 * (v_end / vf - 1), t_end, fl, 100 * (fl / loss - 1), bal, side, cpu))
    lines += ['', 'The rolling speed is the mean of the centre\'s speed (momentum_x / m) after 0.22 s; the slip ends '
              'where the friction\'s account stops growing (within 1e-3 of the loss). p_y: the momentum across the '
              'rolling direction, which the structured mesh\'s Kuhn cut (not symmetric about the rolling plane) '
              'gives the ball; the rigid body has none.', '',
              '![speed of the centre](figures/friction-sphere.png)', '']
    with open(a.doc, 'w') as f:
        f.write('\n'.join(lines))
    try:
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 3.5))
        tt = np.linspace(0.0, 0.25, 200)
        ax.plot(tt, np.minimum(MU * G * tt, vf), 'k--', label='rigid ball')
        for n, t, v in curves:
            ax.plot(t, v, label='TET10, N = %d' % n)
        ax.set_xlabel('t (s)')
        ax.set_ylabel('centre speed (m/s)')
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(a.figures, 'friction-sphere.png'), dpi=110)
    except ImportError:
        pass
    print('wrote %s' % a.doc)


if __name__ == '__main__':
    main()
