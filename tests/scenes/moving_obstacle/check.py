"""Moving rigid obstacles (issue 35, item 6; docs/input.md, "Moving obstacles"): OBSTACLE …
VELOCITY vx vy [FUNCTION f], a plane or a circle translated rigidly, its gap written at each
step's end, its work booked in the external work, the impact corrections in its frame
(src/contact/contact_frame.f90).

- a free bar hit by a wall moving at v0 is the fixed-wall impact seen from the wall: velocities
  equal to the fixed-wall run's plus v0 (1e-9 v0) under every impact mode, the balance at
  round-off, the wall's work the bar's energy;
- a bar crushed by a piston at constant V against a fixed wall (a body touching a moving and a
  fixed obstacle): the staircase of the exact solution, (2k+1) ρcAV at the piston, 2k ρcAV at the
  wall (1 %), the balance at round-off under every mode;
- a point mass hit by an inclined plane moving obliquely: Newton's law relative to the plane
  for e = 1, 0.5, 0 to round-off under AUTO, PAPER and PERSIST, the dissipated energy
  (1 - e²) ½ m (n.v_rel)², the tangential velocity untouched;
- a mass pushed by a piston whose velocity is a SMOOTH_STEP or a POINTS table: it follows the
  piston (second order in h; exactly under a uniform acceleration), leaves it at the final velocity, the piston's work = its energy;
  a mass on a spring driven by a SINE piston: the balance at round-off;
- a pendulum inside a cylinder moving at constant velocity: the fixed cylinder's motion in the
  moving frame (1e-12 of the travel); a rigid sphere moving into a point mass off-centre: the
  mass's speed relative to the sphere kept to round-off, the exact rebound at first order in h;
- a free QUAD4 block, still or spinning, landing on a floor that moves obliquely: the fixed
  floor's run plus the floor's velocity, no momentum along the floor (frictionless);
- a restart with a sine-driven wall continues bit for bit; bad input.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

MODES = ['AUTO', 'PERSIST', 'PAPER', 'SYMMETRIC', 'MASSLESS']
RHO, E, A = 7800.0, 2.1e11, 1e-4
C = np.sqrt(E / RHO)
BAR = """LINE      bar   FROM 0.0001 0  TO 1.0001 0  ELEMENTS 100  TYPE BAR2
MATERIAL  steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION   rod   AREA 1e-4
MODEL     bar   MATERIAL steel SECTION rod MASS LUMPED
FIX       bar UY
TIME      STEP 1e-6 END 1e-3
OUTPUT    HISTORY EVERY 1  FIELDS EVERY 0  PROBE bar.start UX  PROBE bar.start VX  PROBE bar.end VX
"""
MASS = """NODE m AT %s
ELEMENT p TYPE MASS NODES m
SECTION s MASS 2
MODEL p SECTION s
"""


def bar_frame():
    fixed = sc.write_scene('bar_fixed.dat', BAR + 'INITIAL bar VELOCITY -1 0\n'
                           'OBSTACLE wall NODES bar.start POINT 0 0 NORMAL 1 0\n')
    moving = sc.write_scene('bar_moving.dat', BAR + 'OBSTACLE wall NODES bar.start POINT 0 0 NORMAL 1 0 VELOCITY 1 0\n')
    for mode in MODES:
        a = sc.run_ok(fixed, ['SCHEME.IMPACT=' + mode])
        b = sc.run_ok(moving, ['SCHEME.IMPACT=' + mode])
        pa, pb, hb = sc.probes(a), sc.probes(b), sc.history(b)
        t = pa['time']
        dv = max(np.max(np.abs(pb['bar.start.VX'] - pa['bar.start.VX'] - 1)),
                 np.max(np.abs(pb['bar.end.VX'] - pa['bar.end.VX'] - 1)))
        du = np.max(np.abs(pb['bar.start.UX'] - pa['bar.start.UX'] - t))
        bal = np.max(np.abs(hb['balance'])) / np.max(hb['kinetic'] + hb['internal'])
        sc.report_measured('bar hit by a wall moving at v0, IMPACT %s: the fixed wall\'s run plus v0 (velocities 1e-9 v0, '
                           'displacements 1e-12 m), |balance| <= 1e-12 of E' % mode, dv <= 1e-9 and du <= 1e-12 and
                           bal <= 1e-12, 'velocity %.1e, displacement %.1e, balance %.1e' % (dv, du, bal))
        if mode == 'PERSIST':
            work = hb['external'][-1]
            sc.report_measured('bar hit by a moving wall: the wall\'s work is the bar\'s energy (1e-12)',
                               abs(work - hb['kinetic'][-1] - hb['internal'][-1]) <= 1e-12 * work, 'work %.6f J' % work)


def crush():
    scene = sc.write_scene('crush.dat', BAR.replace('0.0001 0  TO 1.0001', '0 0  TO 1') +
                           'OBSTACLE wall NODES bar.start POINT 0 0 NORMAL 1 0\n'
                           'OBSTACLE piston NODES bar.end POINT 1.0001 0 NORMAL -1 0 VELOCITY -1 0\n')
    f0 = RHO * C * A * 1.0
    t0, tl = 1e-4, 1.0 / C
    for mode in MODES:
        out = sc.run_ok(scene, ['SCHEME.IMPACT=' + mode])
        bal, _ = sc.relative_balance(out)
        ok = bal <= 1e-12
        detail = 'balance %.1e' % bal
        if mode == 'AUTO':
            c = sc.contacts(out)
            worst = 0.0
            for name, sign, plateaus in [('piston', -1, [(0, 1), (2, 3)]), ('wall', 1, [(1, 2), (3, 4)])]:
                sel = c['contact'] == name
                t, f = c['time'][sel], sign * c['force_x'][sel] / f0
                for k, level in plateaus:
                    # the middle half of the plateau between the fronts at t0 + k L/c and t0 + (k + 2) L/c
                    lo, hi = t0 + (k + 0.5) * tl, t0 + (k + 1.5) * tl
                    m = np.mean(f[(t > lo) & (t < hi)])
                    worst = max(worst, abs(m / (level if name == 'piston' else level) - 1) if level else abs(m))
            sc.report_measured('bar crushed by a piston at V against a wall: plateaus (2k+1) ρcAV at the piston, '
                               '2k ρcAV at the wall (1 %)', worst <= 0.01, 'worst %.2e' % worst)
        sc.report_measured('bar crushed by a piston against a fixed wall, IMPACT %s: |balance| <= 1e-12 of E' % mode,
                           ok, detail)


def oblique_mass():
    scene = sc.write_scene('oblique.dat', MASS % '0 0.5' + """OBSTACLE wall NODES m POINT -0.2 0 NORMAL 0.6 0.8 VELOCITY 1.5 0.5
TIME STEP 1e-3 END 0.6
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE m VX PROBE m VY
""")
    n, w = np.array([0.6, 0.8]), np.array([1.5, 0.5])
    for e in [1.0, 0.5, 0.0]:
        vr = -w - (1 + e) * (n @ -w) * n
        vex = vr + w
        diss = (1 - e * e) * 0.5 * 2 * (n @ w)**2
        for mode in ['AUTO', 'PAPER', 'PERSIST']:
            out = sc.run_ok(scene, ['SCHEME.IMPACT=' + mode, 'OBSTACLE.RESTITUTION=%g' % e])
            p, h = sc.probes(out), sc.history(out)
            err = max(abs(p['m.VX'][-1] - vex[0]), abs(p['m.VY'][-1] - vex[1]))
            derr = abs(h['impact_dissipated'][-1] - diss)
            bal = np.max(np.abs(h['balance']))
            sc.report_measured('mass hit by an inclined plane moving obliquely, e = %g, IMPACT %s: Newton\'s law relative to '
                               'the plane (1e-13), dissipated (1 - e²) ½ m (n.v_rel)² (1e-13), balance 1e-13' % (e, mode),
                               err <= 1e-13 * 3 and derr <= 1e-13 * 4 and bal <= 1e-13 * 7,
                               'velocity %.1e, dissipated %.1e, balance %.1e' % (err, derr, bal))


def pushed(fn, vfinal, tag):
    text = MASS % '0 0' + fn + """OBSTACLE piston NODES m POINT 0 0 NORMAL 1 0 VELOCITY 3 0 FUNCTION f
TIME STEP 1e-3 END 0.2
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE m UX PROBE m VX
"""
    scene = sc.write_scene('push_%s.dat' % tag, text)
    errs = []
    for h in [1e-3, 5e-4]:
        out = sc.run_ok(scene, ['TIME.STEP=%g' % h])
        p, hist = sc.probes(out), sc.history(out)
        t = p['time']
        wall = 3 * vfinal(t)
        on = t <= 0.1
        errs.append(np.max(np.abs(p['m.UX'][on] - wall[on])))
        bal = np.max(np.abs(hist['balance']))
        sc.report_measured('mass pushed by a piston (%s), h = %g: leaves it at 3 m/s (1e-4), the piston\'s work = its '
                           'kinetic energy, balance 1e-12' % (tag, h), abs(p['m.VX'][-1] / 3 - 1) <= 1e-4 and
                           abs(hist['external'][-1] - hist['kinetic'][-1]) <= 1e-12 * 9 and bal <= 1e-12 * 9,
                           'v = %.8f, balance %.1e' % (p['m.VX'][-1], bal))
    if tag == 'POINTS':   # (a constant acceleration: the trapezoidal rule is exact)
        sc.report_measured('mass pushed by a piston accelerating uniformly (POINTS): it follows it exactly (1e-13 m)',
                           max(errs) <= 1e-13, 'errors %.2e, %.2e' % tuple(errs))
    else:
        sc.report_measured('mass pushed by a piston (%s): it follows the piston at second order in h' % tag,
                           errs[1] <= errs[0] / 3.5 and errs[0] <= 1e-5, 'errors %.2e, %.2e' % tuple(errs))


def smooth_integral(t):
    s = np.clip(t / 0.1, 0, 1)
    return 0.1 * s**4 * (2.5 - 3 * s + s * s) + np.maximum(t - 0.1, 0)


def table_integral(t):
    return np.where(t < 0.05, 0.5 * t * t / 0.05, 0.025 + (t - 0.05))


def sine_spring():
    scene = sc.write_scene('sine_spring.dat', """NODE a AT 0 0
NODE b AT 0.1 0
ELEMENT k TYPE SPRING NODES a b
ELEMENT m TYPE MASS NODES b
MATERIAL sk ELASTIC YOUNG 4e4
SECTION sm MASS 1
MODEL k MATERIAL sk
MODEL m SECTION sm
FIX a UX UY
FIX b UY
FUNCTION f SINE AMPLITUDE 1 FREQUENCY 30
OBSTACLE piston NODES b POINT 0.1002 0 NORMAL -1 0 VELOCITY -0.2 0 FUNCTION f RESTITUTION 0.7
TIME STEP 1e-4 END 0.5
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE b UX
""")
    for mode in ['AUTO', 'PAPER', 'PERSIST']:
        out = sc.run_ok(scene, ['SCHEME.IMPACT=' + mode])
        h = sc.history(out)
        nimp = np.count_nonzero(np.diff(h['active_contacts']) > 0)
        bal = np.max(np.abs(h['balance'])) / np.max(h['kinetic'] + h['internal'])
        sc.report_measured('mass on a spring hit by a sine-driven piston (e = 0.7), IMPACT %s: several impacts, '
                           '|balance| <= 1e-12 of E' % mode, nimp >= 3 and bal <= 1e-12,
                           '%d impacts, balance %.1e' % (nimp, bal))


def moving_circles():
    pend = MASS % '0 -1' + """GRAVITY GY -9.81
INITIAL m VELOCITY %s
OBSTACLE bowl NODES m SPHERE 0 0 RADIUS 1 INSIDE %s
TIME STEP 1e-3 END 2
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE m UX PROBE m UY
"""
    a = sc.run_ok(sc.write_scene('pend_fixed.dat', pend % ('1.6213 0', '')))
    b = sc.run_ok(sc.write_scene('pend_moving.dat', pend % ('4.6213 -1', 'VELOCITY 3 -1')))
    pa, pb = sc.probes(a), sc.probes(b)
    t = pa['time']
    d = max(np.max(np.abs(pb['m.UX'] - 3 * t - pa['m.UX'])), np.max(np.abs(pb['m.UY'] + t - pa['m.UY'])))
    bal = np.max(np.abs(sc.history(b)['balance'])) / 12.0
    sc.report_measured('pendulum inside a cylinder moving at (3, -1) m/s: the fixed cylinder\'s motion in its frame '
                       '(1e-12 of the 6 m travel), balance 1e-12', d <= 6e-12 and bal <= 1e-12,
                       'difference %.1e m, balance %.1e' % (d, bal))
    ball = sc.write_scene('ball.dat', MASS % '0 0.3' + """OBSTACLE ball NODES m SPHERE -1.1 0 RADIUS 1 OUTSIDE VELOCITY 2 0
TIME STEP 1e-3 END 0.3
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE m VX PROBE m VY
""")
    n, w = np.array([np.sqrt(1 - 0.09), 0.3]), np.array([2.0, 0.0])
    vex = -w - 2 * (n @ -w) * n + w
    errs = []
    for h in [1e-3, 1e-4]:
        p = sc.probes(sc.run_ok(ball, ['TIME.STEP=%g' % h]))
        v = np.array([p['m.VX'][-1], p['m.VY'][-1]])
        errs.append(np.linalg.norm(v - vex))
        rel = abs(np.linalg.norm(v - w) - 2.0)
        sc.report_measured('rigid sphere moving into a mass off-centre, h = %g: its speed relative to the sphere kept '
                           '(1e-12)' % h, rel <= 1e-12, '%.1e' % rel)
    sc.report_measured('rigid sphere moving into a mass off-centre: the rebound converges at first order in h',
                       errs[1] <= errs[0] / 5 and errs[0] <= 2e-3, 'errors %.2e, %.2e' % tuple(errs))


def block_floor():
    block = """RECTANGLE b ORIGIN 0 0.001 SIZE 0.1 0.05 ELEMENTS 8 4 TYPE QUAD4
MATERIAL al ELASTIC YOUNG 7e10 POISSON 0.3 DENSITY 2700
SECTION s THICKNESS 0.01
MODEL b MATERIAL al SECTION s
TIME STEP 2e-6 END 1.5e-3
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE b.top_right VX PROBE b.top_right VY PROBE b.bottom_left VY
"""
    a = sc.run_ok(sc.write_scene('block_fixed.dat', block + 'INITIAL b VELOCITY -0.5 -2\n'
                                 'OBSTACLE floor NODES b.bottom POINT 0 0 NORMAL 0 1\n'))
    for mode in ['AUTO', 'PERSIST', 'PAPER']:
        b = sc.run_ok(sc.write_scene('block_moving.dat', block + 'OBSTACLE floor NODES b.bottom POINT 0 0 NORMAL 0 1 '
                                     'VELOCITY 0.5 2\n'), ['SCHEME.IMPACT=' + mode])
        if mode != 'AUTO':
            a = sc.run_ok(sc.write_scene('block_fixed.dat', block + 'INITIAL b VELOCITY -0.5 -2\n'
                                         'OBSTACLE floor NODES b.bottom POINT 0 0 NORMAL 0 1\n'), ['SCHEME.IMPACT=' + mode])
        pa, pb, hb = sc.probes(a), sc.probes(b), sc.history(b)
        dv = max(np.max(np.abs(pb['b.top_right.VX'] - pa['b.top_right.VX'] - 0.5)),
                 np.max(np.abs(pb['b.top_right.VY'] - pa['b.top_right.VY'] - 2)))
        px = np.max(np.abs(hb['momentum_x']))
        events = np.count_nonzero(np.diff(hb['active_contacts']) != 0)
        sc.report_measured('QUAD4 block on a floor moving at (0.5, 2) m/s, IMPACT %s: the fixed floor\'s run plus the '
                           'floor\'s velocity (1e-9 m/s), no momentum along the floor (1e-12 kg m/s)' % mode,
                           dv <= 1e-9 and px <= 1e-12 and events >= 2,
                           'velocity %.1e, momentum_x %.1e, %d changes of the active set' % (dv, px, events))


def spinning_block():
    block = """RECTANGLE b ORIGIN 0 0.002 SIZE 0.1 0.05 ELEMENTS 8 4 TYPE QUAD4
MATERIAL al ELASTIC YOUNG 7e10 POISSON 0.3 DENSITY 2700
SECTION s THICKNESS 0.01
MODEL b MATERIAL al SECTION s
INITIAL b ANGULAR_VELOCITY 30 ABOUT 0.05 0.027
TIME STEP 2e-6 END 3e-3
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE b.top_right VX PROBE b.top_right VY
"""
    fixed = sc.write_scene('spin_fixed.dat', block + 'INITIAL b VELOCITY -0.5 -2\n'
                           'OBSTACLE floor NODES b.bottom POINT 0 0 NORMAL 0 1\n')
    moving = sc.write_scene('spin_moving.dat', block + 'OBSTACLE floor NODES b.bottom POINT 0 0 NORMAL 0 1 VELOCITY 0.5 2\n')
    for mode in ['AUTO', 'PERSIST', 'PAPER']:
        a = sc.run_ok(fixed, ['SCHEME.IMPACT=' + mode])
        b = sc.run_ok(moving, ['SCHEME.IMPACT=' + mode])
        pa, pb, hb = sc.probes(a), sc.probes(b), sc.history(b)
        dv = max(np.max(np.abs(pb['b.top_right.VX'] - pa['b.top_right.VX'] - 0.5)),
                 np.max(np.abs(pb['b.top_right.VY'] - pa['b.top_right.VY'] - 2)))
        px = np.max(np.abs(hb['momentum_x'] - hb['momentum_x'][0]))
        events = np.count_nonzero(np.diff(hb['active_contacts']) != 0)
        bal = np.max(np.abs(hb['balance'])) / np.max(hb['kinetic'] + hb['internal'])
        sc.report_measured('spinning QUAD4 block landing on a corner on a floor moving at (0.5, 2) m/s, IMPACT %s: the '
                           'fixed floor\'s run plus its velocity (1e-9 m/s), momentum along the floor kept (1e-12), '
                           'balance 1e-12' % mode, dv <= 1e-9 and px <= 1e-12 and bal <= 1e-12 and events >= 2,
                           'velocity %.1e, momentum_x %.1e, balance %.1e, %d changes of the active set'
                           % (dv, px, bal, events))


def restart():
    scene = sc.write_scene('restart_wall.dat', BAR + 'FUNCTION f SINE AMPLITUDE 1 FREQUENCY 500\n'
                           'OBSTACLE wall NODES bar.start POINT 0 0 NORMAL 1 0 VELOCITY 2 0 FUNCTION f\n')
    same, detail = sc.restart_same(scene, ['OUTPUT.CHECKPOINT=100'], '5e-4', ('history.csv', 'probes.csv', 'events.csv'))
    sc.report('a sine-driven wall: a restart continues bit for bit', same, detail)


def bad_input():
    base = MASS % '0 1' + 'FUNCTION g SINE AMPLITUDE 1 FREQUENCY 2\n'
    cases = [('POINT 0 0 NORMAL 0 1 FUNCTION g', 'VELOCITY'), ('POINT 0 0 NORMAL 0 1 VELOCITY 1 0 FUNCTION h', 'unknown'),
             ('POINT 0 0 NORMAL 0 1 VELOCITY 1', 'VELOCITY'), ('SPHERE 0 0 RADIUS 0.5 OUTSIDE FUNCTION g', 'VELOCITY')]
    for i, (tail, word) in enumerate(cases):
        scene = sc.write_scene('bad_moving%d.dat' % i, base + 'OBSTACLE o NODES m ' + tail + '\nTIME STEP 1e-3 END 1e-2\n')
        rc, err, out = sc.run(scene, outdir=sc.new_dir('never'))
        sc.report('OBSTACLE … %s: exit 2, file:line, the word' % tail, rc == 2 and ':6: OBSTACLE' in err and
                  word in err and not os.path.exists(out), err.strip())


bar_frame()
crush()
oblique_mass()
pushed('FUNCTION f SMOOTH_STEP T 0.1\n', smooth_integral, 'SMOOTH_STEP')
pushed('FUNCTION f POINTS 0 0 0.05 1 1 1\n', table_integral, 'POINTS')
sine_spring()
moving_circles()
block_floor()
spinning_block()
restart()
bad_input()
