"""INITIAL group ANGULAR_VELOCITY w ABOUT x y (issue 32, item 1, the 2D part; docs/input.md): a rigid
spin ω × (X - x0) added to the velocity a VELOCITY statement gives the same group.

- a free steel square (QUAD8, KINEMATICS LARGE, consistent mass), 0.1 m a side about (0.05, 0.05),
  spinning at 10 rad/s about its centre and moving at 1 m/s along x: at t = 0 the kinetic energy
  ½ I ω² + ½ m v², the momentum m v and the angular momentum about the origin I ω + m (x_c × v)
  exactly (1e-13: the rigid field is in the elements' span); over 200 steps of a quarter turn the
  momentum and the angular momentum kept (1e-11: steel, Newton to TOLERANCE), the balance within
  TOLERANCE x E;
- a beam node gets ω on RZ and ω × (X - x0) on UX, UY (1e-15);
- bad input: two spins on a node, ABOUT missing, ABOUT without ANGULAR_VELOCITY, a spin in an
  axisymmetric model: exit 2 naming the statement.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

SQUARE = """RECTANGLE sq ORIGIN 0 0 SIZE 0.1 0.1 ELEMENTS 4 4 TYPE QUAD8
MATERIAL st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
MODEL sq MATERIAL st PLANE STRAIN MASS CONSISTENT KINEMATICS LARGE
"""


def square():
    scene = sc.write_scene('spin.dat', SQUARE + """INITIAL sq ANGULAR_VELOCITY 10 ABOUT 0.05 0.05
INITIAL sq VELOCITY 1 0
TIME STEP 7.853981633974483e-4 END 0.15707963267948966
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0
""")
    h = sc.history(sc.run_ok(scene))
    m, i_c, w, v = 78.0, 78.0 * 0.01 / 6, 10.0, 1.0
    ke, px, lz = 0.5 * i_c * w**2 + 0.5 * m * v**2, m * v, i_c * w - m * 0.05 * v
    err = max(abs(h['kinetic'][0] / ke - 1), abs(h['momentum_x'][0] / px - 1), abs(h['angular_momentum'][0] / lz - 1),
              abs(h['momentum_y'][0]) / px)
    sc.report_measured('spinning square at t = 0: ½ I ω² + ½ m v², m v, I ω + m x_c × v (1e-13)', err <= 1e-13,
                       '%.1e' % err)
    drift = max(np.max(np.abs(h['angular_momentum'] / lz - 1)), np.max(np.abs(h['momentum_x'] / px - 1)))
    bal = np.max(np.abs(h['balance'])) / ke
    sc.report_measured('spinning square over a quarter turn: momentum and angular momentum kept (1e-11), |balance| '
                       '<= 1e-10 of E (TOLERANCE)', drift <= 1e-11 and bal <= 1e-10 and len(h['step']) == 201,
                       'momenta %.1e, balance %.1e' % (drift, bal))


def beam():
    scene = sc.write_scene('spin_beam.dat', """LINE b FROM -0.5 0 TO 0.5 0 ELEMENTS 10 TYPE BEAM2
MATERIAL st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
SECTION s AREA 1e-4 INERTIA 8.333333333333333e-10 HEIGHT 0.01
MODEL b MATERIAL st SECTION s MASS CONSISTENT KINEMATICS LARGE
INITIAL b ANGULAR_VELOCITY 2 ABOUT 0 0.1
TIME STEP 1e-3 END 1e-2
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE b.end VX PROBE b.end VY PROBE b.end VRZ
""")
    p = sc.probes(sc.run_ok(scene))
    err = max(abs(p['b.end.VX'][0] - 0.2), abs(p['b.end.VY'][0] - 1.0), abs(p['b.end.VRZ'][0] - 2.0))
    sc.report_measured('spinning BEAM2 bar about (0, 0.1): the end node\'s velocity ω × (X - x0) = (0.2, 1) and '
                       'rotation rate ω = 2 (1e-15)', err <= 1e-15, '%.1e' % err)


def bad_input():
    cases = [('INITIAL sq ANGULAR_VELOCITY 1 ABOUT 0 0\nINITIAL sq ANGULAR_VELOCITY 2 ABOUT 0 0\n', 'already spins'),
             ('INITIAL sq ANGULAR_VELOCITY 1\n', 'needs ABOUT'),
             ('INITIAL sq VELOCITY 1 0 ABOUT 0 0\n', 'ABOUT goes with ANGULAR_VELOCITY')]
    for k, (stmt, word) in enumerate(cases):
        scene = sc.write_scene('spin_bad%d.dat' % k, SQUARE + stmt + 'TIME STEP 1e-4 END 1e-3\n')
        rc, err, out = sc.run(scene, outdir=sc.new_dir('never'))
        sc.report('bad spin (%s): exit 2, the statement and the word' % word,
                  rc == 2 and ': INITIAL sq' in err and word in err and not os.path.exists(out), err.strip())
    axi = sc.write_scene('spin_axi.dat', SQUARE.replace('PLANE STRAIN', 'AXISYMMETRIC').replace(' KINEMATICS LARGE', '') +
                         'INITIAL sq ANGULAR_VELOCITY 1 ABOUT 0 0\nTIME STEP 1e-4 END 1e-3\n')
    rc, err, out = sc.run(axi, outdir=sc.new_dir('never'))
    sc.report('a spin in an axisymmetric model: exit 2, naming ANGULAR_VELOCITY',
              rc == 2 and "at 'ANGULAR_VELOCITY'" in err and not os.path.exists(out), err.strip())


square()
beam()
bad_input()
