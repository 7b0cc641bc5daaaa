"""STATIC preload (issue 35, item 2; docs/input.md, "Static preload"): the structure at rest under
the loads and gravity of the start time, then the dynamics from that equilibrium.

- a steel beam resting on two knife-edges (two OBSTACLE conditions, no vertical support: its
  vertical translation and rotation are held by contact only) under gravity: the static mid-span
  deflection equals 5 w L^4 / (384 EI) (exact for Hermite beams under M g) to 1e-9, the contact
  force equals the weight to 1e-10, and left alone for 1000 steps the kinetic energy stays
  <= 1e-12 of the strain energy (no spurious vibration), under IMPACT PERSIST and the default;
- a cantilever clamped under gravity: the static support reactions RY and MZ at t = 0 equal the
  weight and its moment w L^2 / 2 to 1e-10, and the kinetic energy stays <= 1e-12 of the strain
  energy over 1000 steps;
- a bolt-like preload, then an impact: two spring-mass oscillators loaded so that both sit at
  d = 0.01 m, hit one another; the run from the preload is the unloaded run shifted by d (linear
  with a node-to-node contact whose gap only sees the difference) to 1e-12 of the motion, the
  contact force the same, and its balance starts and stays at zero (<= 1e-12 of E); a restart
  from its checkpoint writes the same files byte for byte;
- an elastoplastic bar (BAR2, E = 2e11, σy = 2e8, H_ISO = 2e10) pulled to twice its yield force in
  10 increments: its static elongation equals L (σ/E + (σ - σy)/H), the laws' work the loads' work
  (yield at an increment's end: each increment is linear), then at rest under the held load;
- the elastica (KINEMATICS LARGE, P L^2/EI = 5, STATIC STEPS 5): the tip at (0.71379, 0.38763) L
  (Mattiasson) within 5e-4 L;
- a plate pulled by IMPOSE on 81 nodes: the static reaction E t H ε, at rest after;
- a static analysis alone (TIME END = START): the cantilever's P L^3/(3 EI) and P L (1e-12);
- bad input: a free rigid mode (a point mass held by nothing) named, STEPS 0.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

E, RHO, A, I, L, G = 2.1e11, 7800.0, 1e-4, 8.333333333333333e-10, 1.0, 9.81
W = RHO * A * L * G
BEAM = """LINE      beam  FROM 0 0  TO 1 0  ELEMENTS 20  TYPE BEAM2
MATERIAL  steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION   sq    AREA 1e-4 INERTIA 8.333333333333333e-10 HEIGHT 0.01
MODEL     beam  MATERIAL steel SECTION sq MASS CONSISTENT
GRAVITY   GY -9.81
STATIC
TIME      STEP 1e-5 END 0.01
"""


def at_rest(tag, out):
    h = sc.history(out)
    ke = np.max(h['kinetic']) / h['internal'][0]
    sc.report_measured('%s: left alone, max kinetic <= 1e-12 of the strain energy over %d steps' % (tag, len(h['step']) - 1),
                       ke <= 1e-12 and len(h['step']) == 1001, '%.1e' % ke)


def knife_edges(impact):
    tag = 'beam on two knife-edges (IMPACT %s)' % (impact or 'default')
    scene = sc.write_scene('knife_%s.dat' % impact, BEAM + """OBSTACLE  left  NODES beam.start POINT 0 0 NORMAL 0 1
OBSTACLE  right NODES beam.end POINT 0 0 NORMAL 0 1
FIX       beam.start UX
OUTPUT    HISTORY EVERY 1  FIELDS EVERY 0  PROBE beam.mid UY
""" + ('SCHEME IMPACT %s\n' % impact if impact else ''))
    out = sc.run_ok(scene)
    p = sc.probes(out)
    exact = -5 * W * L ** 3 / (384 * E * I)
    if impact:
        sc.close('%s: static mid-span deflection = 5wL^4/(384EI)' % tag, p['beam.mid.UY'][0], exact, 1e-9)
    c = sc.contacts(out)
    f = c['force_y'][c['step'] == 1].sum()     # the mean force of the first step
    sc.close('%s: the contacts carry the weight' % tag, f, W, 1e-10)
    # each support half of it (MASSLESS's moved mass once gave the load a moment: 3.8266 / 3.8252 N)
    fl = c['force_y'][(c['step'] == 1) & (c['contact'] == 'left')][0]
    sc.close('%s: each knife-edge carries half the weight' % tag, fl, W / 2, 1e-10)
    at_rest(tag, out)


def cantilever():
    scene = sc.write_scene('clamped.dat', BEAM + """FIX beam.start UX UY RZ
OUTPUT    HISTORY EVERY 1  FIELDS EVERY 0  PROBE beam.start RY PROBE beam.start MZ PROBE beam.end UY
""")
    out = sc.run_ok(scene)
    p = sc.probes(out)
    sc.close('clamped cantilever: static reaction RY = the weight', p['beam.start.RY'][0], W, 1e-10)
    sc.close('clamped cantilever: static reaction MZ = w L^2 / 2', p['beam.start.MZ'][0], W * L / 2, 1e-10)
    at_rest('clamped cantilever', out)


BOLT = """NODE b1 AT 0 0
NODE m1 AT 1 0
NODE m2 AT 1.02 0
NODE b2 AT 2.02 0
ELEMENT s1 TYPE SPRING NODES b1 m1
ELEMENT s2 TYPE SPRING NODES m2 b2
ELEMENT p1 TYPE MASS NODES m1
ELEMENT p2 TYPE MASS NODES m2
MATERIAL k1 ELASTIC YOUNG 1e4
MATERIAL k2 ELASTIC YOUNG 1e3
SECTION one MASS 1
SECTION half MASS 0.5
MODEL s1 MATERIAL k1
MODEL s2 MATERIAL k2
MODEL p1 SECTION one
MODEL p2 SECTION half
FIX b1 ALL
FIX b2 ALL
FIX m1 UY
FIX m2 UY
INITIAL m2 VELOCITY -2 0
GAP hit PAIRS m1 m2
TIME STEP 1e-4 END 0.3
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE m1 UX PROBE m2 UX PROBE b1 RX
"""


def bolt():
    d = 0.01
    free = sc.run_ok(sc.write_scene('bolt_free.dat', BOLT))
    pre = sc.run_ok(sc.write_scene('bolt_pre.dat', BOLT + 'LOAD l1 NODES m1 FORCE 100 0\nLOAD l2 NODES m2 FORCE 10 0\n'
                                   'STATIC\n'))
    pf, pp = sc.probes(free), sc.probes(pre)
    sc.close('preload: the spring is stretched to F/k', pp['m1.UX'][0], d, 1e-12)
    sc.close('preload: the static base reaction is -F', pp['b1.RX'][0], -100.0, 1e-12)
    dev = max(np.max(np.abs(pp['m1.UX'] - d - pf['m1.UX'])), np.max(np.abs(pp['m2.UX'] - d - pf['m2.UX'])))
    amp = np.max(np.abs(pf['m2.UX']))
    sc.report_measured('preload then impact: the unloaded run shifted by F/k (<= 1e-12 of the motion)',
                       dev <= 1e-12 * amp, '%.1e of %.3g m' % (dev / amp, amp))
    cf, cp = sc.contacts(free), sc.contacts(pre)
    dc = np.max(np.abs(cf['force_x'] - cp['force_x'])) / np.max(np.abs(cf['force_x']))
    sc.report_measured('preload then impact: the same contact force (1e-10)', dc <= 1e-10 and np.max(np.abs(cf['force_x'])) > 0,
                       '%.1e' % dc)
    same, detail = sc.restart_same(sc.write_scene('bolt_pre_ck.dat', BOLT + 'LOAD l1 NODES m1 FORCE 100 0\n'
                                                  'LOAD l2 NODES m2 FORCE 10 0\nSTATIC\n'),
                                   ['OUTPUT.CHECKPOINT=500'], '0.15', ('history.csv', 'probes.csv', 'contacts.csv'))
    sc.report('preload then impact: stopped and restarted from its checkpoint, the same files byte for byte', same, detail)
    bal, _ = sc.relative_balance(pre)
    h = sc.history(pre)
    sc.report_measured('preload then impact: the balance starts at zero and stays <= 1e-12 of E',
                       h['balance'][0] == 0 and bal <= 1e-12, '%.1e' % bal)


def plastic_bar():
    sy, hh, ee, area = 2e8, 2e10, 2e11, 1e-4
    f = 2 * sy * area
    scene = sc.write_scene('plastic_bar.dat', """LINE bar FROM 0 0 TO 1 0 ELEMENTS 4 TYPE BAR2
MATERIAL m ELASTOPLASTIC YOUNG 2e11 YIELD 2e8 H_ISO 2e10 DENSITY 7800
SECTION s AREA 1e-4
MODEL bar MATERIAL m SECTION s MASS CONSISTENT
FIX bar.start UX UY
FIX bar UY
LOAD pull NODES bar.end FORCE %r 0
STATIC STEPS 10
TIME STEP 1e-6 END 1e-3
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE bar.end UX PROBE bar.start RX
""" % f)
    rc, err, out = sc.run(scene)
    if not sc.report('elastoplastic bar: STATIC STEPS 10 runs', rc == 0, err.strip()):
        return
    p = sc.probes(out)
    s = f / area
    sc.close('elastoplastic bar: static elongation L (σ/E + (σ - σy)/H)', p['bar.end.UX'][0], s / ee + (s - sy) / hh, 1e-10)
    sc.close('elastoplastic bar: static reaction', p['bar.start.RX'][0], -f, 1e-10)
    h = sc.history(out)
    wint = (s ** 2 / (2 * ee) + (s ** 2 - sy ** 2) / (2 * hh)) * area * L
    sc.close('elastoplastic bar: the internal energy at t = 0 is the work of σ along the path', h['internal'][0], wint, 1e-10)
    sc.close('elastoplastic bar: the dissipated column at t = 0 is the plastic work (σ² - σy²)/(2H)',
             h['dissipated'][0], (s ** 2 - sy ** 2) / (2 * hh) * area * L, 1e-10)
    at_rest('elastoplastic bar', out)


def elastica():
    scene = sc.write_scene('elastica_static.dat', """LINE beam FROM 0 0 TO 1 0 ELEMENTS 20 TYPE BEAM2
MATERIAL m ELASTIC YOUNG 1e6 DENSITY 1
SECTION s AREA 1 INERTIA 1e-6 HEIGHT 3.4641016151377544e-3
MODEL beam MATERIAL m SECTION s MASS CONSISTENT KINEMATICS LARGE
FIX beam.start UX UY RZ
LOAD tip NODES beam.end FORCE 0 -5
STATIC STEPS 5
TIME STEP 1e-3 END 1
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE beam.end UX PROBE beam.end UY
""")
    rc, err, out = sc.run(scene)
    if not sc.report('elastica (LARGE, P L^2/EI = 5): STATIC STEPS 5 runs', rc == 0, err.strip()):
        return
    p = sc.probes(out)
    w, u = -p['beam.end.UY'][0], -p['beam.end.UX'][0]
    sc.report_measured('elastica: the static tip at (0.71379, 0.38763) L within 5e-4 L',
                       abs(w - 0.71379) <= 5e-4 and abs(u - 0.38763) <= 5e-4, 'w %.5f, u %.5f' % (w, u))
    at_rest('elastica', out)


def imposed():
    """A plate pulled by IMPOSE on its right side (81 imposed DOFs: the contact system's Schur
    columns, with κ c c' on the imposed rows), plane stress, free to contract: the static reaction
    is E t H ε (1e-10), and at rest after."""
    scene = sc.write_scene('imposed_plate.dat', """RECTANGLE pl ORIGIN 0 0 SIZE 1 1 ELEMENTS 20 40 TYPE QUAD8
MATERIAL st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
SECTION sl THICKNESS 0.01
MODEL pl MATERIAL st SECTION sl PLANE STRESS
FIX pl.left UX
FIX pl.bottom_left UY
FUNCTION one POINTS 0 1 1 1
IMPOSE pl.right UX VALUE 1e-3 FUNCTION one
STATIC
TIME STEP 1e-6 END 1e-3
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE pl.right RX
""")
    rc, err, out = sc.run(scene)
    if not sc.report('plate pulled by 81 imposed DOFs: STATIC runs', rc == 0, err.strip()):
        return
    p = sc.probes(out)
    sc.close('plate pulled by IMPOSE: static reaction E t H ε', p['pl.right.RX'][0], 2e11 * 0.01 * 1.0 * 1e-3, 1e-10)
    at_rest('plate pulled by IMPOSE', out)


def static_alone():
    """A static analysis alone (TIME END equal to START): a cantilever under a tip load, the state of
    t = 0 written (one row) and nothing stepped: tip deflection P L^3 / (3 EI) and clamp moment P L
    (1e-12)."""
    scene = sc.write_scene('static_alone.dat', """LINE beam FROM 0 0 TO 1 0 ELEMENTS 10 TYPE BEAM2
MATERIAL steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION sq AREA 1e-4 INERTIA 8.333333333333333e-10 HEIGHT 0.01
MODEL beam MATERIAL steel SECTION sq
FIX beam.start UX UY RZ
LOAD tip NODES beam.end FORCE 0 -10
STATIC
TIME STEP 1e-4 END 0
OUTPUT PROBE beam.end UY PROBE beam.start MZ
""")
    out = sc.run_ok(scene)
    p = sc.probes(out)
    sc.report('STATIC alone (TIME END = START): one row, t = 0', len(p['time']) == 1 and p['time'][0] == 0.0,
              '%d rows' % len(p['time']))
    sc.close('STATIC alone: tip deflection P L^3/(3 EI)', p['beam.end.UY'][0], -10.0 / (3 * E * I), 1e-12)
    sc.close('STATIC alone: clamp moment P L', p['beam.start.MZ'][0], 10.0, 1e-12)
    rc, err, out = sc.run(sc.write_scene('time_zero.dat', """LINE beam FROM 0 0 TO 1 0 ELEMENTS 10 TYPE BEAM2
MATERIAL steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION sq AREA 1e-4 INERTIA 8.333333333333333e-10 HEIGHT 0.01
MODEL beam MATERIAL steel SECTION sq
FIX beam.start UX UY RZ
TIME STEP 1e-4 END 0
"""), outdir=sc.new_dir('never'))
    sc.report('TIME END = START without MODES or STATIC: exit 2 naming END', rc == 2 and "at 'END'" in err and
              not os.path.exists(out), err.strip())


def bad_input():
    free = sc.write_scene('static_free.dat', """NODE a AT 0 0
ELEMENT m TYPE MASS NODES a
SECTION s MASS 1
MODEL m SECTION s
FIX a UY
GRAVITY GY -9.81
STATIC
TIME STEP 1e-3 END 0.01
""")
    rc, err, out = sc.run(free)
    sc.report('a free rigid mode: exit 2, file:line, STATIC, the mode named, nothing written',
              rc == 2 and 'static_free.dat:7: STATIC' in err and 'free translation along x' in err
              and not os.path.exists(out), err.strip())
    rc, err, out = sc.run(free, ['STATIC.STEPS=0'])
    sc.report('STATIC STEPS 0: exit 2 naming STEPS', rc == 2 and 'STEPS' in err and not os.path.exists(out), err.strip())


knife_edges('PERSIST')
knife_edges('')
cantilever()
bolt()
plastic_bar()
elastica()
imposed()
static_alone()
bad_input()
