"""Curved rigid obstacles (issue 35, item 6; docs/input.md, "Contact"): OBSTACLE name NODES g
SPHERE|CYLINDER x y RADIUS r INSIDE|OUTSIDE, the node's normal through the centre, its row
re-linearized at every step and, during the step, the discrete gradient of the gap between the
step's ends (src/contact/contact_geometry.f90, pair_circle): a held contact does no work.

- a point mass sliding inside a frictionless circle of radius R (a pendulum of length R, 30
  degrees): the period against the exact 4 sqrt(R/g) K(sin(θ0/2)), second order in h (1.4e-5,
  8.7e-7 at h = 4e-3, 1e-3 s), |balance| <= 1e-11 of E, the mass on the circle (1e-9 R), under the
  default (PERSIST) and IMPACT PAPER;
- a point mass sliding off a frictionless sphere from its top at v0: it leaves where
  cos θ = (2 + v0²/(g R))/3 (within the step's travel), the energy exact;
- STATIC in a bowl: a mass pushed sideways by m g tan 30° rests at 30 degrees (1e-9), then stays;
- Hertz: a rigid sphere pressed into a block (axisymmetric, STATIC): the force within 1.5 % of
  Hertz's law at two indentations, F ∝ δ^(3/2), the contact edge within a node spacing of Hertz's;
- bad input: RADIUS <= 0, no INSIDE/OUTSIDE, POINT with SPHERE, a node at the centre.
"""
import csv
import os
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

G, V0 = 9.81, 1.6213
MASS = """NODE m AT %s
ELEMENT p TYPE MASS NODES m
SECTION s MASS 1
MODEL p SECTION s
GRAVITY GY -9.81
"""


def ellipk(m):
    """K(m) by the arithmetic-geometric mean."""
    a, b = 1.0, np.sqrt(1.0 - m)
    for _ in range(60):
        a, b = 0.5 * (a + b), np.sqrt(a * b)
    return np.pi / (2 * a)


def pendulum(h, impact=''):
    scene = sc.write_scene('pendulum%s.dat' % impact, MASS % '0 -1' + """INITIAL m VELOCITY %r 0
OBSTACLE bowl NODES m SPHERE 0 0 RADIUS 1 INSIDE
TIME STEP 1e-3 END 4.2
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE m UX PROBE m UY
""" % V0 + ('SCHEME IMPACT %s\n' % impact if impact else ''))
    out = sc.run_ok(scene, ['TIME.STEP=%r' % h])
    p = sc.probes(out)
    x, y, t = p['m.UX'], -1 + p['m.UY'], p['time']
    th0 = np.arccos(1 - V0**2 / (2 * G))
    period = 4 * np.sqrt(1 / G) * ellipk(np.sin(th0 / 2)**2)
    s = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    tc = t[s] - x[s] * (t[s + 1] - t[s]) / (x[s + 1] - x[s])
    bal, _ = sc.relative_balance(out)
    return (tc[1] - tc[0]) / period - 1, bal, np.max(np.abs(np.hypot(x, y) - 1))


def pendulums():
    errs = []
    for h in [4e-3, 1e-3]:
        err, bal, dev = pendulum(h)
        errs.append(abs(err))
        sc.report_measured('pendulum inside a circle, h = %g: |balance| <= 1e-11 of E, on the circle (1e-9 R)' % h,
                           bal <= 1e-11 and dev <= 1e-9, 'balance %.1e, off the circle %.1e' % (bal, dev))
    rate = np.log(errs[0] / errs[1]) / np.log(4)
    sc.report_measured('pendulum inside a circle: the period converges to the exact one at second order',
                       errs[1] <= 2e-6 and rate >= 1.8, 'errors %.2e, %.2e, rate %.2f' % (errs[0], errs[1], rate))
    err, bal, dev = pendulum(1e-3, 'PAPER')
    sc.report_measured('pendulum, IMPACT PAPER: the same period, the energy exact', abs(err) <= 2e-6 and bal <= 1e-11,
                       'period %.1e, balance %.1e' % (err, bal))


def slide_off():
    v0 = 0.5
    scene = sc.write_scene('dome.dat', MASS % '0 1' + """INITIAL m VELOCITY %r 0
OBSTACLE dome NODES m SPHERE 0 0 RADIUS 1 OUTSIDE
TIME STEP 1e-4 END 1
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE m UX PROBE m UY
""" % v0)
    out = sc.run_ok(scene)
    p = sc.probes(out)
    with open(os.path.join(out, 'events.csv')) as f:
        rel = [int(e['step']) for e in csv.DictReader(f) if e['event'] == 'release']
    exact = (2 + v0**2 / G) / 3
    if not sc.report('sliding off a sphere: it leaves once', len(rel) == 1, '%d releases' % len(rel)):
        return
    k = rel[0]
    x, y = p['m.UX'][k], 1 + p['m.UY'][k]
    c = y / np.hypot(x, y)
    # the release is seen at the end of a step: within the angle one step travels (v h / R)
    v = np.sqrt(v0**2 + 2 * G * (1 - exact))
    tol = np.sin(np.arccos(exact)) * v * 1e-4
    sc.report_measured('sliding off a sphere: it leaves at cos θ = (2 + v0²/gR)/3 within a step', abs(c - exact) <= tol,
                       'cos %.6f vs %.6f (step %.1e)' % (c, exact, tol))
    bal, _ = sc.relative_balance(out)
    sc.report_measured('sliding off a sphere: |balance| <= 1e-11 of E', bal <= 1e-11, '%.1e' % bal)


def bowl_static():
    """STATIC with a curved obstacle: a point mass in a bowl pushed sideways by F = m g tan 30°
    comes to rest at 30 degrees (the rows linearized at each iterate, the bowl's curvature -Λ∇²g in
    the Newton matrix), then stays there within 1e-6 R, its energy balance within 1e-10 of m g R."""
    f = G * np.tan(np.radians(30))
    scene = sc.write_scene('bowl_static.dat', MASS % '0 -1' + """LOAD push NODES m FORCE %r 0
OBSTACLE bowl NODES m SPHERE 0 0 RADIUS 1 INSIDE
STATIC STEPS 3
TIME STEP 1e-3 END 1
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE m UX PROBE m UY
""" % f)
    rc, err, out = sc.run(scene)
    if not sc.report('STATIC in a bowl: runs', rc == 0, err.strip()):
        return
    p = sc.probes(out)
    x, y = p['m.UX'], p['m.UY']
    err0 = max(abs(x[0] - 0.5), abs(y[0] - (1 - np.cos(np.radians(30)))))
    sc.report_measured('STATIC in a bowl: at rest at 30 degrees (1e-9 R)', err0 <= 1e-9, '%.1e' % err0)
    drift = np.max(np.hypot(x - x[0], y - y[0]))
    bal = np.max(np.abs(sc.history(out)['balance'])) / G
    sc.report_measured('STATIC in a bowl, then left alone: within 1e-6 R, |balance| <= 1e-10 m g R', drift <= 1e-6 and
                       bal <= 1e-10, 'drift %.1e R, balance %.1e m g R' % (drift, bal))


HERTZ = """GMSH b FILE %s
MATERIAL st ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
MODEL b.block MATERIAL st AXISYMMETRIC
OBSTACLE ball NODES b.top SPHERE 0 0.01 RADIUS 0.01 OUTSIDE
FUNCTION one POINTS 0 1 1 1
IMPOSE b.bottom UY VALUE %r FUNCTION one
FIX b.bottom UX
STATIC STEPS 4
TIME STEP 1e-7 END 1e-7
OUTPUT HISTORY EVERY 1 FIELDS EVERY 1 PROBE b.bottom RY
"""


def hertz_static():
    """A rigid sphere (R = 10 mm) pressed into a steel block (axisymmetric, 40 x 40 mm, QUAD8 graded
    from 20 µm at the contact: tools/block_mesh.py) by STATIC: the base pushed up by δ. Hertz's
    half-space law F = 4/3 E* sqrt(R) δ^(3/2) within 1.5 % at δ = 2.5 and 10 µm (the finite block:
    +1.35, +0.94, +0.63 % at 10, 20, 40 mm and δ = 2.5 µm, falling with its size), F ∝ δ^(3/2) to
    0.5 %, and the edge of the contact (between the last node on the sphere, gap 0, and the first
    one off it) within one node spacing of Hertz's radius a = (3 F R / 4 E*)^(1/3)."""
    msh = os.path.join(sc.TMP, 'hertz_block.msh')
    subprocess.run(['/usr/bin/python3', os.path.join(sc.ROOT, 'tools', 'block_mesh.py'), '0.04', '0.04', '2e-5', '1.12', msh],
                   check=True)
    es = 2.1e11 / (1 - 0.3**2)
    kh = 4 / 3 * es * np.sqrt(0.01)
    forces = []
    for d in [2.5e-6, 1e-5]:
        out = sc.run_ok(sc.write_scene('hertz_%g.dat' % d, HERTZ % (msh, d)))
        f = sc.probes(out)['b.bottom.RY'][0]
        forces.append(f)
        sc.report_measured('Hertz (rigid sphere on a block, STATIC): F within 1.5 %% of 4/3 E* sqrt(R) δ^1.5 at δ = %g m' % d,
                           abs(f / (kh * d**1.5) - 1) <= 0.015, 'F = %.2f N, ratio %.4f' % (f, f / (kh * d**1.5)))
        with h5py.File(os.path.join(out, 'fields.h5'), 'r') as h:
            x = h['mesh/coordinates'][()]
            u = h['step_000000/displacement'][()]
        top = np.nonzero(np.abs(x[:, 1]) < 1e-12)[0]
        top = top[np.argsort(x[top, 0])]
        gap = np.hypot(x[top, 0] + u[top, 0], u[top, 1] - 0.01) - 0.01
        touching = gap <= 1e-12 * 0.01
        last = np.max(np.nonzero(touching)[0])
        a = (3 * abs(f) * 0.01 / (4 * es))**(1 / 3)
        lo, hi = x[top[last], 0], x[top[last + 1], 0]
        sc.report_measured('Hertz at δ = %g m: the contact edge within one node spacing of Hertz\'s radius' % d,
                           lo - (hi - lo) <= a <= hi and not touching[last + 1:].any(),
                           'a = %.4e m, edge between nodes at %.4e and %.4e' % (a, lo, hi))
    slope = np.log(forces[1] / forces[0]) / np.log(4)
    sc.report_measured('Hertz: F ∝ δ^(3/2) (0.5 %)', abs(slope / 1.5 - 1) <= 5e-3, 'exponent %.4f' % slope)


def bad_input():
    cases = [('RADIUS 0 INSIDE', 'RADIUS'), ('RADIUS 1', 'INSIDE or OUTSIDE'),
             ('RADIUS 1 INSIDE POINT 0 0', 'POINT goes with a plane'), ('RADIUS 1 INSIDE', 'centre')]
    for i, (tail, word) in enumerate(cases):
        node = '0 0' if word == 'centre' else '0 -1'
        scene = sc.write_scene('bad_sphere%d.dat' % i, MASS % node + 'OBSTACLE o NODES m SPHERE 0 0 ' + tail +
                               '\nTIME STEP 1e-3 END 1e-2\n')
        rc, err, out = sc.run(scene, outdir=sc.new_dir('never'))
        sc.report('OBSTACLE … SPHERE %s: exit 2, file:line, the word' % tail, rc == 2 and ':6: OBSTACLE' in err and
                  word in err and not os.path.exists(out), err.strip())


pendulums()
slide_off()
bowl_static()
hertz_static()
bad_input()
