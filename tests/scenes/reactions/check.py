"""Support reactions (issue 13, item 6): PROBE group RX|RY|MZ writes the force (moment) the
supports exert on the structure, summed over the group's fixed DOFs of that direction: the mean
of the step, from the fixed rows' momentum balance of the scheme (src/assembly/reactions.f90).

- the elastic-plastic spring of inputs/spring_plastic.dat (SUBSTEPS 100: eq (9)'s correction
  acts): the whole structure's momentum, m (v(n+1) - v(n)) / h, equals the base reaction of the
  step (the only external force), before, during and after yield, to the iteration's residual
  (SCHEME TOLERANCE 1e-14 here);
- the oscillator of tests/scenes/sdof_period: R̄ = -½ k (u(n) + u(n+1)) exactly;
- a clamped cantilever under gravity ramped in over 0.2 s, damped to rest (ALPHA 105: every mode
  decays as e^{-52.5 t}; consistent mass: part of the weight goes straight into the support):
  RY = m g and MZ = m g L/2 within 1e-10 (mean of the last 0.2 s, see cantilever());
- a reaction probe on a group with no fixed DOF of its direction is an input error;
- PROBE group MZ ABOUT x y on a continuum clamp (QUAD8, no RZ): the moment of the loads about
  the point (1e-10), ABOUT misplaced or incomplete refused.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402


def with_output(scene, output):
    lines = [ln for ln in open(os.path.join(sc.ROOT, scene)).read().split('\n') if not ln.startswith('OUTPUT')]
    return sc.write_scene(os.path.basename(scene), '\n'.join(lines + [output]) + '\n')


def plastic_spring():
    scene = with_output('inputs/spring_plastic.dat', 'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE tip UX tip VX base RX')
    # The momentum identity holds to the iteration's residual: a tight TOLERANCE.
    out = sc.run_ok(scene, ['SCHEME.TOLERANCE=1e-14'])
    p = sc.read_csv(os.path.join(out, 'probes.csv'))
    h = sc.read_csv(os.path.join(out, 'history.csv'))
    dt = np.diff(p['time'])
    mom = 1.0 * np.diff(p['tip.VX']) / dt
    r = p['base.RX'][1:]
    rel = np.max(np.abs(mom - r)) / np.max(np.abs(r))
    sc.report('plastic spring: m Δv/h of the structure = the base reaction of every step (%.1e)' % rel, rel <= 1e-12,
              '%.3e' % rel)
    sc.report('plastic spring: it yields (the reaction reaches the yield force 100 N)',
              np.max(np.abs(r)) > 99.9 and h['dissipated'][-1] > 0, 'max |R| %.4g' % np.max(np.abs(r)))


def oscillator():
    scene = with_output('tests/scenes/sdof_period/sdof.dat', 'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE tip UX base RX')
    out = sc.run_ok(scene)
    p = sc.read_csv(os.path.join(out, 'probes.csv'))
    u, r = p['tip.UX'], p['base.RX']
    pred = -0.5 * 8.0 * (u[1:] + u[:-1])
    rel = np.max(np.abs(r[1:] - pred)) / np.max(np.abs(pred))
    sc.report('oscillator: R̄ = -½ k (u(n) + u(n+1)) (%.1e); at t = 0, -k u0' % rel,
              rel <= 1e-13 and abs(r[0] + 8.0 * u[0]) <= 1e-15, '%.3e, r0 %r' % (rel, r[0]))


CANTILEVER = """LINE      beam  FROM 0 0  TO 1 0  ELEMENTS 20  TYPE BEAM2
MATERIAL  steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION   rect  AREA 1e-4 INERTIA 8.333333333e-10 HEIGHT 0.01
MODEL     beam  MATERIAL steel SECTION rect MASS CONSISTENT DAMPING ALPHA 105
FIX       beam.start UX UY RZ
FUNCTION  ramp POINTS 0 0 0.2 1
GRAVITY   GY -9.81 FUNCTION ramp
TIME      STEP 1e-4 END 1.0
OUTPUT    HISTORY EVERY 1  FIELDS EVERY 0  PROBE beam.start RX beam.start RY beam.start MZ beam.end UY
"""


def cantilever():
    out = sc.run_ok(sc.write_scene('cantilever_gravity.dat', CANTILEVER))
    p = sc.read_csv(os.path.join(out, 'probes.csv'))
    w = 7800 * 1e-4 * 1.0 * 9.81
    # The step means over the last 0.2 s: the trapezoid rule does not damp the highest modes
    # (its amplification tends to -1 as ωh grows, damped or not), which the ramp's end excites
    # at the 1e-8 level; over 2000 steps they average out.
    last = p['time'] > 0.8
    ry, mz, rx = (np.mean(p[c][last]) for c in ('beam.start.RY', 'beam.start.MZ', 'beam.start.RX'))
    sc.report('cantilever at rest under gravity: RY = m g (%.12g vs %.12g N)' % (ry, w), abs(ry - w) <= 1e-10 * w,
              '%.3e' % ((ry - w) / w))
    sc.report('cantilever at rest under gravity: MZ = m g L/2 (%.12g vs %.12g N m)' % (mz, w / 2),
              abs(mz - w / 2) <= 1e-10 * w, '%.3e' % ((mz - w / 2) / w))
    sc.report('cantilever: RX = 0 (%.1e N)' % rx, abs(rx) <= 1e-12 * w, '%r' % rx)


def refused():
    scene = sc.write_scene('free_reaction.dat', CANTILEVER.replace('PROBE beam.start RX', 'PROBE beam.end RX'))
    rc, err, out = sc.run(scene, outdir=sc.new_dir('never'))
    sc.report('a reaction probe without a fixed DOF in its group is refused',
              rc == 2 and 'no node of the group has this DOF fixed' in err and not os.path.exists(out),
              'exit %d: %r' % (rc, err))


QUADS = """RECTANGLE c ORIGIN 0 0 SIZE 1 0.1 ELEMENTS 20 4 TYPE QUAD8
MATERIAL st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
MODEL c MATERIAL st PLANE STRESS
FIX c.left UX UY
LOAD tip NODES c.bottom_right FORCE 0 -1000
GRAVITY GY -9.81
STATIC
TIME STEP 1e-5 END 1e-4
"""


def moment_about():
    """A QUAD8 cantilever (no RZ: a continuum clamp) at rest under its weight and a tip load:
    PROBE c.left MZ ABOUT x y, the moment of the clamp's reactions about a point, equals the
    moment of the loads about it, P L + m g L/2 (about the clamp's mid-height), and about the
    corner (0, 0) the same (RX = 0)."""
    scene = sc.write_scene('moment_about.dat', QUADS + 'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE c.left RY '
                           'PROBE c.left MZ ABOUT 0 0.05 PROBE c.left RX\n')
    p = sc.probes(sc.run_ok(scene))
    w = 7800 * 0.1 * 9.81
    sc.close('QUAD8 clamp at rest: RY = P + m g', p['c.left.RY'][-1], 1000 + w, 1e-10)
    sc.close('QUAD8 clamp at rest: MZ ABOUT the clamp\'s mid-height = P L + m g L/2', p['c.left.MZ'][-1],
             1000 + w / 2, 1e-10)
    bad = sc.write_scene('about_rx.dat', QUADS + 'OUTPUT PROBE c.left RX ABOUT 0 0\n')
    rc, err, out = sc.run(bad, outdir=sc.new_dir('never'))
    sc.report('ABOUT after RX is refused, naming ABOUT', rc == 2 and 'ABOUT goes with MZ' in err and "at 'ABOUT'" in err
              and not os.path.exists(out), err.strip())
    bad = sc.write_scene('about_short.dat', QUADS + 'OUTPUT PROBE c.left MZ ABOUT 0\n')
    rc, err, out = sc.run(bad, outdir=sc.new_dir('never'))
    sc.report('ABOUT without both coordinates is refused', rc == 2 and 'ABOUT needs the point' in err, err.strip())


plastic_spring()
oscillator()
cantilever()
refused()
moment_about()
