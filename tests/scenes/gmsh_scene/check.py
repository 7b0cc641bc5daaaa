"""A scene built on a Gmsh mesh (tests/data/square_quad4.msh, unit square, 2 x 2 QUAD4).

clamped.dat: left edge clamped, right edge launched; the run succeeds, the linear elastic
energy balance stays at round-off (|balance| <= 1e-12 x max(kinetic + internal)), the body
moves (kinetic and strain energy exchanged), and the probe on the clamped corner stays 0.
roller.dat: left edge on a vertical roller; the probe on the corner (0, 0) shows the motion.
No vertical support force exists, so the vertical momentum p = 1'M v0 is conserved by the
trapezoidal rule and the kinetic energy never falls below that of the centre of mass,
p^2 / (2 m) with m = rho t = 11 kg and p = 2.75 kg m/s (consistent-mass row sums of the three
right-edge nodes: 1/16 + 1/8 + 1/16 of m, times v0y = 1 m/s): 0.34375 J.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = 'tests/scenes/gmsh_scene/'

rc, err, out = sc.run(HERE + 'clamped.dat')
sc.report('clamped: run succeeds', rc == 0 and os.path.isfile(os.path.join(out, 'history.csv')),
          'exit %d: %s' % (rc, err.strip()))
if rc == 0:
    hist = sc.history(out)
    rel, _ = sc.relative_balance(out)
    print('# clamped: max |balance| / max(kinetic + internal) = %.3e' % rel)
    sc.report('clamped: |balance| <= 1e-12 x total energy', rel <= 1e-12, 'measured %.3e vs <= 1e-12' % rel)
    e = np.max(hist['kinetic'] + hist['internal'])
    sc.report('clamped: the body moves (strain energy reaches > 10 % of the total)', np.max(hist['internal']) > 0.1 * e,
              'max internal %.3e of %.3e' % (np.max(hist['internal']), e))
    p = sc.probes(out)
    sc.report('clamped: the clamped corner does not move', np.all(p['sq.corner.UY'] == 0.0),
              'max |u| = %.3e' % np.max(np.abs(p['sq.corner.UY'])))

rc, err, out = sc.run(HERE + 'roller.dat')
sc.report('roller: run succeeds', rc == 0, 'exit %d: %s' % (rc, err.strip()))
if rc == 0:
    hist = sc.history(out)
    p = sc.probes(out)
    uy = p['sq.corner.UY']
    sc.report('roller: probe shows motion of the corner', np.max(np.abs(uy)) > 1e-3,
              'max |UY| = %.3e m' % np.max(np.abs(uy)))
    sc.report('roller: corner UX held by the roller', np.all(p['sq.corner.UX'] == 0.0))
    rel, _ = sc.relative_balance(out)
    print('# roller: max |balance| / max(kinetic + internal) = %.3e' % rel)
    sc.report('roller: |balance| <= 1e-12 x total energy', rel <= 1e-12, 'measured %.3e vs <= 1e-12' % rel)
    kmin = np.min(hist['kinetic'])
    bound = 2.75**2 / (2.0 * 11.0)
    sc.report('roller: kinetic >= p^2 / 2m (vertical momentum conserved)', kmin >= bound * (1.0 - 1e-9),
              'min kinetic %.12g vs p^2/2m %.12g' % (kmin, bound))

# tags.dat: the nodes of events.csv are Gmsh's tags (10, 20, 50 on the bottom side), and a
# message about a node names its tag too (the same mesh with the wall above the bottom side).
out = sc.run_ok(HERE + 'tags.dat')
with open(os.path.join(out, 'events.csv')) as f:
    f.readline()
    nodes = sorted(set(int(line.split(',')[3]) for line in f))
sc.report('events.csv names the Gmsh node tags 10, 20, 50', nodes == [10, 20, 50], str(nodes))
with open(HERE + 'tags.dat') as f:
    text = f.read().replace('POINT 0 -0.001', 'POINT 0 0.25').replace('../../data/', os.path.abspath('tests/data') + '/')
rc, err, _ = sc.run(sc.write_scene('tags_inside.dat', text))
sc.report('an initial penetration names the Gmsh tag (node 10, 20 or 50)', rc == 2 and any(
    'node %d ' % t in err for t in (10, 20, 50)), err.strip()[:300])
