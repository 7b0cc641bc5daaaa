"""Axisymmetric models (issue 32, item 3; docs/input.md, "Axisymmetric models").

`MODEL … AXISYMMETRIC`: x = r >= 0, y the axis, the hoop strain u_r/r, every mass, force and energy
over the whole circumference (2π r in the weights), the nodes on the axis held at u_r = 0 by rebond.
Exact cases, each element type:
- Lamé: a thick cylinder (a = 0.1, b = 0.2 m, held axially: ε_z = 0) under an internal pressure
  ramped and damped to rest: u_r(a), u_r(b) and the hoop stress sigma_tt (fields.h5, named so) of
  the inner elements against u = (1+ν) p a²/(E (b²-a²)) ((1-2ν) r + b²/r) and
  σ_θ = p a² (1 + b²/r²)/(b² - a²);
- the mass of the ring, ρ π (b² - a²) L, from the kinetic energy of a rigid axial motion (½ M v²);
- a solid cylinder (nodes on the axis) under an external pressure: the uniform state u_r = -p (1+ν)
  (1-2ν) r / E, the axis nodes held (stdout says so) and the history's momentum_x and
  angular_momentum zero (a ring has neither);
- the breathing of a thin ring (t/R = 1/100): period 2π R sqrt(ρ (1-ν²)/E) within 0.1 %;
- an elastic cylinder (ν = 0) dropped on a rigid plane at the defaults: the balance to 1e-10 of E, the
  axial momentum's change equal to the contact impulse, the contact lasting 2L/c, and the same
  rebound as the plane-stress bar of the same length (the 1D wave, whatever the section).
- Lamé in 3D: the same cylinder as a HEX20 quarter (tools/cylinder_mesh.py, GMSH) against Lamé (1e-5)
  and against the axisymmetric QUAD8 run at every output step, transient included (1e-4).
"""
import os
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

E, NU, RHO, P = 2e11, 0.3, 7800.0, 1e8
A, B, L = 0.1, 0.2, 0.02

LAME = sc.write_scene('lame.dat', """
RECTANGLE c ORIGIN 0.1 0 SIZE 0.1 0.02 ELEMENTS 20 2 TYPE QUAD8
MATERIAL  st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
MODEL     c MATERIAL st AXISYMMETRIC DAMPING ALPHA 2e4
FIX       c.bottom UY
FIX       c.top UY
FUNCTION  ramp POINTS 0 0 1e-3 1
PRESSURE  c.left VALUE 1e8 FUNCTION ramp
TIME      STEP 2e-6 END 6e-3
OUTPUT    HISTORY EVERY 100 FIELDS EVERY 3000 PROBE c.bottom_left UX PROBE c.bottom_right UX
""")


def u_lame(r):
    return (1 + NU) / E * P * A * A / (B * B - A * A) * ((1 - 2 * NU) * r + B * B / r)


def s_hoop(r):
    return P * A * A / (B * B - A * A) * (1 + B * B / r / r)


def last_fields(out):
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        steps = sorted(k for k in f if k.startswith('step_'))
        g = f[steps[-1]]
        return {k: np.array(g[k]) for k in g if k.startswith('sigma')}, np.array(f['mesh/coordinates']), \
            np.array(f['mesh/topology'])


errors = {}
for etype, nx, tol_u, tol_s in (('QUAD8', 10, 2e-5, 2e-2), ('TRI6', 10, 1e-4, 3e-2), ('QUAD4', 40, 2e-4, 2e-2),
                                ('TRI3', 40, 1e-3, 2e-2), ('QUAD4', 20, 1e-3, 2e-2), ('TRI6', 20, 2e-5, 2e-2)):
    out = sc.run_ok(LAME, ['RECTANGLE.TYPE=' + etype, 'RECTANGLE.ELEMENTS=%d 2' % nx])
    p = sc.probes(out)
    cols = list(p)[2:]
    ua, ub = p[cols[0]][-1], p[cols[1]][-1]
    err = max(abs(ua / u_lame(A) - 1), abs(ub / u_lame(B) - 1))
    errors[etype, nx] = err
    sc.report_measured('Lamé %s %d x 2: u_r(a), u_r(b) within %g' % (etype, nx, tol_u), err <= tol_u,
                       'u(a) %.6e (exact %.6e), u(b) %.6e (exact %.6e), %.2e' % (ua, u_lame(A), ub, u_lame(B), err))
    sig, xyz, _ = last_fields(out)
    sc.report('Lamé %s: fields.h5 names the hoop stress sigma_tt (no sigma_zz)' % etype,
              'sigma_tt' in sig and 'sigma_zz' not in sig, ', '.join(sorted(sig)))
    if 'sigma_tt' in sig:
        # the largest element-mean hoop stress, at the innermost column, against Lamé's mean over the
        # column's section (σ_θ varies like 1/r²)
        dr = (B - A) / nx
        r0, r1 = A, A + dr
        exact = P * A * A / (B * B - A * A) * (1 + B * B * 2 * np.log(r1 / r0) / (r1 * r1 - r0 * r0))
        inner = np.max(sig['sigma_tt'])
        sc.report_measured('Lamé %s %d x 2: the inner hoop stress within %g %% of Lamé' % (etype, nx, 100 * tol_s),
                           abs(inner / exact - 1) <= tol_s, '%.5e vs %.5e (%+.3f %%)' % (inner, exact,
                                                                                       100 * (inner / exact - 1)))
for etype, rate in (('QUAD4', 1.9), ('TRI6', 1.9)):   # (TRI6: its 3-point rule integrates the 1/r terms to order 2)
    r = np.log2(errors[etype, 20 if etype == 'QUAD4' else 10] / errors[etype, 40 if etype == 'QUAD4' else 20])
    sc.report_measured('Lamé %s: the displacement error converges at order >= %g' % (etype, rate), r >= rate,
                       'order %.2f' % r)

# --- the ring's mass: a rigid axial motion, ½ M v² ---------------------------------------------
MOVE = sc.write_scene('move.dat', """
RECTANGLE c ORIGIN 0.1 0 SIZE 0.1 0.02 ELEMENTS 5 2 TYPE QUAD8
MATERIAL  st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
MODEL     c MATERIAL st AXISYMMETRIC
INITIAL   c VELOCITY 0 3
TIME      STEP 1e-6 END 1e-5
OUTPUT    HISTORY EVERY 1
""")
m_exact = RHO * np.pi * (B * B - A * A) * L
for etype in ('QUAD4', 'QUAD8', 'TRI3', 'TRI6'):
    for mass in ('CONSISTENT', 'LUMPED'):
        h = sc.history(sc.run_ok(MOVE, ['RECTANGLE.TYPE=' + etype, 'MODEL.MASS=' + mass]))
        m = 2 * h['kinetic'][0] / 9.0
        sc.close('ring mass %s %s = rho pi (b^2 - a^2) L' % (etype, mass), m, m_exact, 1e-12)
        sc.close('axial momentum %s %s = M v' % (etype, mass), h['momentum_y'][-1], 3 * m_exact, 1e-12)

# --- a solid cylinder under external pressure: the uniform state, the axis held -----------------
SOLID = sc.write_scene('solid.dat', """
RECTANGLE c ORIGIN 0 0 SIZE 0.1 0.02 ELEMENTS 10 2 TYPE QUAD4
MATERIAL  st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
MODEL     c MATERIAL st AXISYMMETRIC DAMPING ALPHA 4e4
FIX       c.bottom UY
FIX       c.top UY
FUNCTION  ramp POINTS 0 0 5e-4 1
PRESSURE  c.right VALUE 1e8 FUNCTION ramp
TIME      STEP 2e-6 END 3e-3
OUTPUT    HISTORY EVERY 50 FIELDS EVERY 1500 PROBE c.center UX PROBE c.bottom_right UX PROBE c.bottom_left UX
""")
for etype in ('QUAD4', 'TRI6'):
    code, err, out = sc.run(SOLID, ['RECTANGLE.TYPE=' + etype], timeout=120)
    sc.report('solid %s: runs' % etype, code == 0, err)
    if code != 0:
        continue
    said = sc.run_limited([sc.REBOND, SOLID, '-o', sc.new_dir(), '--set', 'RECTANGLE.TYPE=' + etype], 120,
                          cwd=sc.ROOT, text=True).stdout
    naxis = 3 if etype == 'QUAD4' else 5
    sc.report('solid %s: stdout says the %d axis nodes are held' % (etype, naxis),
              '%d nodes on the axis (x = 0) of c: u_r = UX = 0 imposed' % naxis in said, said[-600:])
    p = sc.probes(out)
    cols = list(p)[2:]
    u_exact = -P * (1 + NU) * (1 - 2 * NU) / E
    err = max(abs(p[cols[0]][-1] / (0.05 * u_exact) - 1), abs(p[cols[1]][-1] / (0.1 * u_exact) - 1))
    sc.report_measured('solid %s: u_r = -p (1+nu)(1-2nu) r / E (r = R/2, R) within 1e-4' % etype, err <= 1e-4,
                       '%.3e' % err)
    sc.report('solid %s: the axis node held (u_r = 0)' % etype, p[cols[2]][-1] == 0.0, '%g' % p[cols[2]][-1])
    h = sc.history(out)
    sc.report('solid %s: momentum_x and angular_momentum are zero (a ring)' % etype,
              np.all(h['momentum_x'] == 0) and np.all(h['angular_momentum'] == 0))

# --- the breathing of a thin ring: period 2π R sqrt(ρ (1-ν²)/E) ----------------------------------
RING = sc.write_scene('ring.dat', """
RECTANGLE c ORIGIN 0.995 0 SIZE 0.01 0.01 ELEMENTS 1 1 TYPE QUAD8
MATERIAL  st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
MODEL     c MATERIAL st AXISYMMETRIC
FIX       c.bottom UY
FIX       c.top UY
INITIAL   c VELOCITY 1 0
TIME      STEP 1e-6 END 2e-3
OUTPUT    HISTORY EVERY 1 PROBE c.bottom_left UX
""")
p = sc.probes(sc.run_ok(RING))
u = p[list(p)[2]]
t = p['time']
up = np.where((u[:-1] > 0) & (u[1:] <= 0))[0]         # downward zero crossings, interpolated
tz = t[up] - u[up] * (t[up + 1] - t[up]) / (u[up + 1] - u[up])
period = np.mean(np.diff(tz))
exact = 2 * np.pi * 1.0 * np.sqrt(RHO * (1 - NU * NU) / E)
# Newmark's period elongation at ω h: T_h/T = ω h / (2 atan(ω h / 2)) (h = T/750: 3e-6)
wh = 2 * np.pi * 1e-6 / exact
sc.close('breathing ring: period (t/R = 1/100, Newmark elongation removed)', period / (wh / (2 * np.arctan(wh / 2))),
         exact, 1e-3)

# --- an elastic cylinder (nu = 0) dropped on a rigid plane, at the defaults ------------------------
DROP = sc.write_scene('drop.dat', """
RECTANGLE bar ORIGIN 0 0.002 SIZE 0.01 0.2 ELEMENTS 1 20 TYPE QUAD4
MATERIAL  steel ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000
MODEL     bar MATERIAL steel AXISYMMETRIC
INITIAL   bar VELOCITY 0 -100
OBSTACLE  wall NODES bar.bottom POINT 0 0 NORMAL 0 1
TIME      STEP 2e-6 END 1.3e-4
OUTPUT    HISTORY EVERY 1
""")
FLAT = sc.write_scene('flat.dat', """
RECTANGLE bar ORIGIN 0 0.002 SIZE 0.01 0.2 ELEMENTS 1 20 TYPE QUAD4
MATERIAL  steel ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000
SECTION   s THICKNESS 0.01
MODEL     bar MATERIAL steel SECTION s PLANE STRESS
INITIAL   bar VELOCITY 0 -100
OBSTACLE  wall NODES bar.bottom POINT 0 0 NORMAL 0 1
TIME      STEP 2e-6 END 1.3e-4
OUTPUT    HISTORY EVERY 1
""")
out = sc.run_ok(DROP)
h = sc.history(out)
m = 8000 * np.pi * 1e-4 * 0.2
bal, _ = sc.relative_balance(out)
sc.report_measured('drop: |balance| <= 1e-10 of E', bal <= 1e-10, '%.2e' % bal)
c = sc.contacts(out)
imp = np.sum(c['impulse_y'])
dp = h['momentum_y'][-1] - h['momentum_y'][0]
sc.close('drop: the axial momentum gained is the contact impulse', dp, imp, 1e-9)
act = c['time'][c['force_y'] > 0]
sc.report_measured('drop: contact from 2e-5 s for 2L/c = 8e-5 s (within 2 steps)',
                   abs(act.min() - 2e-5) <= 4e-6 and abs(act.max() - act.min() - 8e-5) <= 4e-6,
                   '%.3e to %.3e s' % (act.min(), act.max()))
hf = sc.history(sc.run_ok(FLAT))
v_axi = h['momentum_y'][-1] / m
v_flat = hf['momentum_y'][-1] / (8000 * 1e-4 * 0.2)
sc.report_measured('drop: the rebound of the plane-stress bar (the 1D wave), within 0.2 %',
                   abs(v_axi / v_flat - 1) <= 2e-3, 'axisymmetric %.4f m/s, plane stress %.4f m/s' % (v_axi, v_flat))
sc.report('drop: momentum_x and angular_momentum zero', np.all(h['momentum_x'] == 0) and np.all(h['angular_momentum'] == 0))

# --- KINEMATICS LARGE: at a small amplitude, the small-strain cylinder -------------------------------
for measure in ('GREEN', 'LOG'):
    out = sc.run_ok(LAME, ['MODEL.KINEMATICS=LARGE', 'MODEL.STRAIN_MEASURE=' + measure, 'PRESSURE.VALUE=1e5',
                           'PRESSURE.DEAD='])
    p = sc.probes(out)
    cols = list(p)[2:]
    ua = p[cols[0]][-1] * 1e3                        # scaled to the pressure of u_lame (1e8)
    sc.close('LARGE %s at p = 1e5 Pa (strain 1e-7): u_r(a) of Lamé' % measure, ua, u_lame(A), 2e-5)

# --- the Taylor cylinder (inputs/taylor_bar.dat) at the defaults --------------------------------------
# The finest run (docs/taylor-axisymmetric.md, 16 x 80 at h = 1.25e-7 s): length 21.39 mm, foot radius
# 7.335 mm; issue 38 asks the 4 x 20 foot within 5 % of the converged value.
TAYLOR = os.path.join('inputs', 'taylor_bar.dat')
res = {}
for h in (2.5e-7, 1.25e-7):
    out = sc.run_ok(TAYLOR, ['TIME.STEP=%g' % h, 'OUTPUT.FIELDS=EVERY 0'])
    hist = sc.history(out)
    bal = np.max(np.abs(hist['balance'])) / hist['kinetic'][0]
    sc.report_measured('Taylor cylinder h = %g: |balance| <= 1e-10 of E' % h, bal <= 1e-10, '%.2e' % bal)
    c = sc.contacts(out)
    sc.report_measured('Taylor cylinder h = %g: the wall never crossed (1e-9 m)' % h, np.min(c['min_gap']) >= -1e-9,
                       'min gap %.2e m' % np.min(c['min_gap']))
    sc.close('Taylor cylinder h = %g: the axial momentum gained is the wall\'s impulse' % h,
             hist['momentum_y'][-1] - hist['momentum_y'][0], np.sum(c['impulse_y']), 1e-9)
    it = np.mean(hist['iterations'][1:])
    sc.report_measured('Taylor cylinder h = %g: <= 6 iterations a step, no step retried' % h,
                       it <= 6 and np.all(hist['substeps'] <= 1), '%.2f a step, %d retried' % (it, np.sum(hist['substeps'] > 1)))
    p = sc.probes(out)
    foot = 3.2e-3 + p['bar.bottom_right.UX'][-1]
    length = 32.5e-3 + p['bar.top_left.UY'][-1]
    res[h] = (foot, length)
    diss = hist['dissipated'][-1] / hist['kinetic'][0]
    sc.report_measured('Taylor cylinder h = %g: > 99 %% of the energy dissipated, foot radius and length within 5 %% '
                       'and 1 %% of the 16 x 80 run\'s 7.335 and 21.39 mm' % h,
                       diss > 0.99 and abs(foot / 7.335e-3 - 1) <= 0.05 and abs(length / 21.39e-3 - 1) <= 0.01,
                       '%.2f %%, foot radius %.3f mm, length %.3f mm' % (100 * diss, 1e3 * foot, 1e3 * length))
d = [abs(res[2.5e-7][k] / res[1.25e-7][k] - 1) for k in range(2)]
sc.report_measured('Taylor cylinder: foot radius and length change by < 0.5 % as h halves', max(d) < 5e-3,
                   'foot %.1e, length %.1e' % tuple(d))

# --- Hertz: an elastic sphere on a rigid plane (inputs/hertz_axi.dat), three meshes --------------------
HERE = os.path.dirname(os.path.abspath(__file__))
R_S, V_S = 0.01, 1.0
m_s, t_hertz, f_hertz = sc.hertz_sphere(R_S, 2.1e11, 0.3, 7800.0, V_S)
for tag, msh in (('125 TRI6', os.path.join(HERE, 'hertz_coarse.msh')), ('475 TRI6', os.path.join(sc.ROOT, 'inputs', 'hertz.msh')),
                 ('958 TRI6', os.path.join(HERE, 'hertz_fine.msh'))):
    out = sc.run_ok(os.path.join('inputs', 'hertz_axi.dat'), ['GMSH.FILE=' + msh, 'OUTPUT.FIELDS=EVERY 0'])
    c = sc.contacts(out)
    steps = np.unique(c['step'])
    force = np.array([np.sum(c['force_y'][c['step'] == s]) for s in steps])
    times = np.array([c['time'][c['step'] == s][0] for s in steps])
    on = times[force > 0]
    dur = on.max() - on.min() + 2.5e-7
    h = sc.history(out)
    bal = np.max(np.abs(h['balance'])) / np.max(h['kinetic'] + h['internal'])
    sc.report_measured('Hertz %s: contact duration within 3 %% of %.2f us, peak force within 5 %% of %.0f N, '
                       'rebound 1 m/s (0.1 %%), |balance| <= 1e-10 of E' % (tag, 1e6 * t_hertz, f_hertz),
                       abs(dur / t_hertz - 1) <= 0.03 and abs(force.max() / f_hertz - 1) <= 0.05 and
                       abs(h['momentum_y'][-1] / m_s - V_S) <= 1e-3 and bal <= 1e-10,
                       'duration %.2f us (%+.2f %%), peak %.0f N (%+.2f %%), rebound %.5f m/s, balance %.1e'
                       % (1e6 * dur, 100 * (dur / t_hertz - 1), force.max(), 100 * (force.max() / f_hertz - 1),
                          h['momentum_y'][-1] / m_s, bal))

# --- Lamé in 3D: the thick cylinder as a HEX20 quarter against the axisymmetric model ------------------
# tools/cylinder_mesh.py: a = 0.1, b = 0.2 m, 90 degrees, L = 0.02 m, 10 x 8 x 1 HEX20 (mid-edge nodes on
# the arcs), the symmetry planes and the ends held, the same damped pressure ramp as LAME (QUAD8 10 x 2).
msh = os.path.join(sc.new_dir('cyl'), 'cyl.msh')
os.makedirs(os.path.dirname(msh), exist_ok=True)
subprocess.run(['/usr/bin/python3', os.path.join(sc.ROOT, 'tools', 'cylinder_mesh.py'), msh, '0.1', '0.2', '90', '0.02',
                '10', '8', '1'], check=True, capture_output=True)
LAME3D = sc.write_scene('lame3d.dat', """DIMENSION 3
GMSH      cyl FILE %s
MATERIAL  st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
MODEL     cyl.body MATERIAL st DAMPING ALPHA 2e4
FIX       cyl.theta0 UY
FIX       cyl.theta1 UX
FIX       cyl.bottom UZ
FIX       cyl.top UZ
FUNCTION  ramp POINTS 0 0 1e-3 1
PRESSURE  cyl.inner VALUE 1e8 FUNCTION ramp
GROUP     ia NODES BOX 0.0999 -1e-6 -1e-6 0.1001 1e-6 1e-6 OF cyl.body
GROUP     ib NODES BOX 0.1999 -1e-6 -1e-6 0.2001 1e-6 1e-6 OF cyl.body
TIME      STEP 2e-6 END 6e-3
OUTPUT    HISTORY EVERY 100 FIELDS EVERY 0 PROBE ia UX PROBE ib UX
""" % msh)
p3 = sc.probes(sc.run_ok(LAME3D))
pa = sc.probes(sc.run_ok(LAME, ['RECTANGLE.ELEMENTS=10 2']))
ca = list(pa)[2:]
err3 = max(abs(p3['ia.UX'][-1] / u_lame(A) - 1), abs(p3['ib.UX'][-1] / u_lame(B) - 1))
sc.report_measured('Lamé 3D (HEX20 quarter, 10 x 8 x 1): u_r(a), u_r(b) within 1e-5 of Lamé', err3 <= 1e-5,
                   'u(a) %.7e, u(b) %.7e: %.1e' % (p3['ia.UX'][-1], p3['ib.UX'][-1], err3))
scale = abs(pa[ca[0]]).max()
dev = max(np.abs(p3['ia.UX'] - pa[ca[0]]).max(), np.abs(p3['ib.UX'] - pa[ca[1]]).max()) / scale
sc.report_measured('Lamé: the 3D HEX20 and the axisymmetric QUAD8 runs agree at every output step (the transient '
                   'included) to 1e-4 of u_r(a)', dev <= 1e-4, '%.1e' % dev)
