"""Initial conditions as functions of position (issue 13, item 6): INITIAL group DISPLACEMENT
ux uy [rz] FUNCTION f ALONG X|Y (and VELOCITY), the values times f of each node's coordinate.

- the clamped 1D bar of docs/contact.md (L = E = ρ = 1, 80 BAR2) with u0(x) = ½ − x/2 given as
  a profile: the initial strain energy is 1/8 to round-off, and the run equals the same bar
  started from the static preload (INITIAL STATIC FORCE 0.5, whose solution is that line);
- a velocity profile v0(y) on a vertical column of nodes: the kinetic energy of ½ Σ m v0²;
- FUNCTION with STATIC, ALONG without FUNCTION, ALONG Z: exit 2 naming the word.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

BAR = """LINE      bar FROM 0 0 TO 1 0 ELEMENTS 80 TYPE BAR2
MATERIAL  m ELASTIC YOUNG 1 POISSON 0 DENSITY 1
SECTION   s AREA 1
MODEL     bar MATERIAL m SECTION s MASS CONSISTENT
FIX       bar UY
FIX       bar.end UX
%s
OBSTACLE  wall NODES bar.start POINT 0 0 NORMAL 1 0
TIME      STEP 1.25e-3 END 2.4
SCHEME    IMPACT PERSIST
OUTPUT    HISTORY EVERY 1 FIELDS EVERY 0 PROBE bar.start UX
"""


def bar():
    profile = sc.write_scene('bar_profile.dat', BAR % 'FUNCTION  line POINTS 0 0.5 1 0\nINITIAL   bar DISPLACEMENT 1 0 FUNCTION line ALONG X')
    static = sc.write_scene('bar_static.dat', BAR % 'INITIAL   bar.start STATIC FORCE 0.5 0')
    hp = sc.read_csv(os.path.join(sc.run_ok(profile), 'history.csv'))
    hs = sc.read_csv(os.path.join(sc.run_ok(static), 'history.csv'))
    e0 = hp['internal'][0]
    sc.report('bar: u0(x) = ½ − x/2 as a profile: initial strain energy 1/8 (%.16g)' % e0, abs(e0 - 0.125) <= 1e-15,
              '%r' % e0)
    dk = np.max(np.abs(hp['kinetic'] - hs['kinetic'])) / 0.125
    sc.report('bar: the same run as from the static preload (kinetic energies within %.1e of E)' % dk, dk <= 1e-12,
              '%.3e' % dk)


def column():
    scene = sc.write_scene('column.dat', """LINE      col FROM 0 0 TO 0 2 ELEMENTS 4 TYPE BAR2
MATERIAL  m ELASTIC YOUNG 1e3 POISSON 0 DENSITY 1
SECTION   s AREA 1
MODEL     col MATERIAL m SECTION s MASS LUMPED
FIX       col.start UX UY
FUNCTION  shear POINTS 0 0 2 3
INITIAL   col VELOCITY 1 0 FUNCTION shear ALONG Y
TIME      STEP 1e-4 END 2e-4
""")
    h = sc.read_csv(os.path.join(sc.run_ok(scene), 'history.csv'))
    # lumped masses 0.25 0.5 0.5 0.5 0.25 at y = 0 0.5 1 1.5 2; v0 = 1.5 y; the base is fixed.
    want = 0.5 * sum(m * (1.5 * y) ** 2 for m, y in ((0.5, 0.5), (0.5, 1.0), (0.5, 1.5), (0.25, 2.0)))
    k0 = h['kinetic'][0]
    sc.report('column: v0(y) = 1.5 y gives the kinetic energy ½ Σ m v0² (%.16g vs %.16g)' % (k0, want),
              abs(k0 - want) <= 1e-15 * want, '%r' % k0)


def refused():
    for tag, line, word in (('FUNCTION with STATIC', 'FUNCTION  line POINTS 0 0.5 1 0\nINITIAL   bar.start STATIC FORCE 0.5 0 '
                             'FUNCTION line', 'FUNCTION'),
                            ('ALONG without FUNCTION', 'INITIAL   bar DISPLACEMENT 1 0 ALONG X', 'ALONG'),
                            ('ALONG Z', 'FUNCTION  line POINTS 0 0.5 1 0\nINITIAL   bar DISPLACEMENT 1 0 FUNCTION line ALONG Z',
                             'Z')):
        scene = sc.write_scene('bad_%s.dat' % tag.replace(' ', '_'), BAR % line)
        rc, err, out = sc.run(scene, outdir=sc.new_dir('never'))
        sc.report('%s refused (exit 2, names %s)' % (tag, word),
                  rc == 2 and ": INITIAL" in err and ("at '%s'" % word) in err and not os.path.exists(out),
                  'exit %d: %r' % (rc, err))


bar()
column()
refused()
